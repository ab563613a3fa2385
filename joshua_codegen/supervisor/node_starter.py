"""The node starter: Python nodes forked from one process that imported their types once (joshua_runtime.node_starter)."""

import os
import select
import signal
import socket
import struct
import time

from joshua_codegen.supervisor.children import child_exec
from joshua_codegen.supervisor.common import exit_text, log
from joshua_codegen.supervisor.policy import (
    STARTER_READY_TIMEOUT_S,
    STARTER_REPLY_TIMEOUT_S,
    STARTER_STOP_POLL_S,
    STARTER_STOP_TIMEOUT_S,
    STARTER_TITLE_SLACK,
    STOP_SIGNALS,
)

STARTER_CODE = (
    "import sys; del sys.path[0]; from joshua_runtime.node_starter.server import main; sys.exit(main(sys.argv[1:]))"
)
STARTER_REPLY_BYTES = 4096
STARTER_NAME = "node-starter"  # its name in the supervisor's log


class NodeStarter:
    """The starter process of one supervisor: started at the first node it serves, ended with the supervisor.
    Once it fails, every Python node starts its own interpreter again."""

    def __init__(self, python: str, nodes):
        self.python = python
        self.node_types = sorted({node.spec["type"] for node in nodes})
        self.title_room = max(len(os.fsencode(python)) + len(os.fsencode(node.entrypoint())) + 2 for node in nodes)
        self.pid = None
        self.channel = None
        self.state = "idle"  # idle, starting, ready, failed, stopped
        self.deadline = None  # while starting: when it is given up on if not ready

    def serves(self, node, argv: list[str]) -> bool:
        """Whether the node's process comes from the starter: its Python entrypoint, run with the starter's
        interpreter and no variables of its own (which could change what the imports did)."""
        return (
            self.state not in ("failed", "stopped")
            and argv == [self.python, node.entrypoint()]
            and not node.spec["env"]
        )

    def ready(self, supervisor) -> bool:
        """Whether it can start nodes, started (in the robot's environment, the guard told of it) and waited
        for first when it is not running yet. A stop signal (on the supervisor's wakeup descriptor) ends the
        wait: False."""
        if self.state == "idle":
            self.start({**os.environ, **supervisor.build.robot["env"]}, supervisor.pid)
            if self.pid is not None:
                supervisor.guard.track(self.pid)
        if self.state == "starting":
            self.wait_ready(supervisor)
        return self.state == "ready"

    def start(self, environment: dict[str, str], supervisor: int) -> None:
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        argv = [self.python, "-c", STARTER_CODE, "--socket-fd", str(theirs.fileno()), *self.node_types]
        room = self.title_room + STARTER_TITLE_SLACK - len(b"\0".join(os.fsencode(part) for part in argv))
        argv += [""] * max(0, room)  # empty arguments, room for the command line of each node forked from it
        blocked = STOP_SIGNALS + (signal.SIGCHLD,)
        signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
        try:
            os.set_inheritable(theirs.fileno(), True)
            pid = os.fork()
            if pid == 0:
                ours.close()
                child_exec(argv, environment, supervisor, None, None)
        except OSError as exc:
            ours.close()
            self.fail(f"cannot start: {exc}")
            return
        finally:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, blocked)
            theirs.close()
        self.pid, self.channel, self.state = pid, ours, "starting"
        self.deadline = time.monotonic() + STARTER_READY_TIMEOUT_S
        log(STARTER_NAME, f"started pid {pid}: importing {', '.join(self.node_types)} for the Python nodes")

    def wait_ready(self, supervisor) -> None:
        poller = select.poll()
        poller.register(self.channel.fileno(), select.POLLIN)
        poller.register(supervisor.wakeup, select.POLLIN)
        while self.state == "starting" and not supervisor.requests:
            left = self.deadline - time.monotonic()
            if left <= 0:
                self.fail(f"not ready after {STARTER_READY_TIMEOUT_S:g} s")
                return
            events = dict(poller.poll(left * 1000))
            if events.get(self.channel.fileno()):
                if self.channel.recv(STARTER_REPLY_BYTES) == b"ready":
                    self.state = "ready"
                    log(STARTER_NAME, "ready: Python nodes are forked from it")
                else:
                    self.fail("ended before it was ready")
            elif events.get(supervisor.wakeup):
                supervisor.drain_wakeup()  # a signal: a stop request ends the wait; an exit is reaped after it

    def launch(self, entries, supervisor: int) -> list:
        """Fork the nodes of `entries` ((node, output descriptor or None) each), asked for all at once: for each,
        its pid, an OSError when the starter could not fork it (out of processes, say), or None when the starter
        failed before it answered (it is then ended, and said so)."""
        results = [None] * len(entries)
        try:
            for number, (node, output) in enumerate(entries):
                self.channel.sendmsg([starter_request(number, node, supervisor)], descriptor_message(output))
            poller = select.poll()
            poller.register(self.channel.fileno(), select.POLLIN)
            waiting = len(entries)
            while waiting and poller.poll(STARTER_REPLY_TIMEOUT_S * 1000):
                kind, number, text = parse_reply(self.channel.recv(STARTER_REPLY_BYTES))
                if kind is None or not 0 <= number < len(entries) or results[number] is not None:
                    self.fail(f"answered {text!r}")
                    return results
                results[number] = int(text) if kind == "pid" else OSError(text)
                waiting -= 1
        except OSError as exc:
            self.fail(f"cannot reach it: {exc}")
            return results
        if waiting:
            self.fail(f"no answer for {waiting} of {len(entries)} nodes in {STARTER_REPLY_TIMEOUT_S:g} s")
        return results

    def fail(self, reason: str) -> None:
        log(STARTER_NAME, f"warning: {reason}; each Python node starts its own interpreter from now on")
        self.close()
        self.state = "failed"

    def exited(self, status: int) -> None:
        """Its process ended (reaped by the supervisor)."""
        pid, self.pid = self.pid, None
        if self.state not in ("failed", "stopped"):
            self.fail(f"pid {pid} {exit_text(status)}")

    def stop(self) -> None:
        """The robot stops: it is told to end (its socket closed), and starts nothing more."""
        if self.channel is not None:
            self.channel.close()
            self.channel = None
        self.state = "stopped"

    def close(self) -> None:
        """End it: its socket closed, then killed if it has not exited within STARTER_STOP_TIMEOUT_S."""
        if self.channel is not None:
            self.channel.close()
            self.channel = None
        if self.pid is None:
            return
        deadline = time.monotonic() + STARTER_STOP_TIMEOUT_S
        try:
            while os.waitpid(self.pid, os.WNOHANG) == (0, 0):
                if time.monotonic() > deadline:
                    os.kill(self.pid, signal.SIGKILL)
                    os.waitpid(self.pid, 0)
                    break
                time.sleep(STARTER_STOP_POLL_S)
        except ChildProcessError:  # reaped already
            pass
        self.pid = None


def starter_request(number: int, node, supervisor: int) -> bytes:
    """Request `number`: NUL-separated, the number, the entrypoint, the node's cgroup, the supervisor's pid, then
    the node's environment as NAME=VALUE (joshua_runtime.node_starter reads it)."""
    fields = [str(number), node.entrypoint(), node.processes.path, str(supervisor)]
    fields += [f"{name}={value}" for name, value in node.environment.items()]
    return b"\0".join(os.fsencode(field) for field in fields)


def descriptor_message(output: int | None) -> list:
    return [] if output is None else [(socket.SOL_SOCKET, socket.SCM_RIGHTS, struct.pack("i", output))]


def parse_reply(reply: bytes) -> tuple[str | None, int, str]:
    """("pid", request number, pid) or ("error", request number, text); (None, -1, text) for anything else."""
    text = reply.decode(errors="replace")
    kind, _, rest = text.partition(" ")
    number, _, value = rest.partition(" ")
    if kind not in ("pid", "error") or not number.isdigit() or (kind == "pid" and not value.isdigit()):
        return None, -1, text
    return kind, int(number), value
