"""The control socket: status, restart / stop / start of one node and its log, reload, one JSON line each way."""

import errno
import os
import signal
import socket
import time

from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.control_connection import (
    CONTROL_OUTPUT_LIMIT_BYTES,
    CONTROL_OUTPUT_TOTAL_BYTES,
    ControlConnection,
    LogFollowers,
    close_quietly,
)
from joshua_codegen.supervisor.control_request import RequestError, parse_request, refusal
from joshua_codegen.supervisor.control_socket import SocketFile, may_control, peer_credentials
from joshua_codegen.supervisor.reload import begin_reload
from joshua_codegen.supervisor.robot import ROBOT

CONTROL_SOCKET_VARIABLE = "JOSHUA_CONTROL_SOCKET"  # told to every node, so a dashboard finds the socket
CONTROL_CLIENTS_MAX = 1024  # clients connected at once; one more is answered "too many" and closed
CONTROL_FDS_KEPT = 64  # descriptors never given to clients: the supervisor's own, and its nodes' pipes...
CONTROL_FDS_PER_NODE = 4  # ...and this many more per node
CONTROL_ACCEPTS_PER_TURN = 64  # clients accepted before the loop turns to other work
CONTROL_ACCEPT_BACKOFF_S = 0.5  # out of descriptors (EMFILE): how long the socket stops accepting
CONTROL_TURN_S = 0.01  # time for requests in one turn of the loop; the rest wait for the next (timers run between)
CONTROL_REFUSAL_LOG_S = 10.0  # refused clients of other users are logged at most once in this interval
ACCEPT_OUT_OF_RESOURCES = (errno.EMFILE, errno.ENFILE, errno.ENOBUFS, errno.ENOMEM)


def control_clients_max(fd_limit: int, nodes: int) -> int:
    """How many clients may be connected at once under the open-file limit `fd_limit`, `nodes` running too."""
    return max(1, min(CONTROL_CLIENTS_MAX, fd_limit - CONTROL_FDS_KEPT - CONTROL_FDS_PER_NODE * nodes))


class ControlPlane:
    """Serves the socket for a Supervisor: registers its descriptors in `supervisor.readers` / `writers` (the
    loop's Poller), and is polled by the loop (`poll`, at `deadline()`) to finish node stops and restarts,
    escalate their signals, resume accepting and handle request lines left from an earlier turn.

    Requests (control_request.py): {"command": "status"}, {"command": "restart"|"stop"|"start", "node":
    NAME}, {"command": "logs", "node": NAME, "lines": N, "follow": false|true, "all": false|true}, {"command":
    "reload", "path": BUILD DIRECTORY} (reload.py). Replies:
    {"ok": true, ...} or {"ok": false, "kind": one of REFUSAL_KINDS, "error": "one line"}; a stop or restart
    is answered once it has been done (a stop: SIGINT, SIGTERM after sigint_grace_s, SIGKILL after
    sigterm_grace_s more), a reload once the nodes it stops are gone and their successors started. A start
    of a node that runs and a stop of one that does not (stopped, finished, failed) are both refused as
    conflicts. The socket is a Unix stream socket of mode 0600 in a directory of
    this user's, mode 0700 (control_socket.py); only clients of the same user or root are served, the others
    get one error line.
    """

    def __init__(self, supervisor, path: str, clients_max: int):
        self.supervisor = supervisor
        self.readers = supervisor.readers
        self.writers = supervisor.writers
        self.path = path
        self.clients_max = clients_max
        self.connections = {}  # fd -> ControlConnection
        self.backlog = {}  # fd -> ControlConnection with request lines left for the next turn
        self.followers = LogFollowers()
        self.buffered = 0  # reply bytes every connection holds unsent
        self.pending = {}  # node name -> {"stage", "deadline", "then": callable or None, "waiters": [connection]}
        self.reloading = None  # the Reload under way (reload.py), which answers once its nodes have stopped
        self.since = {}  # node name -> (state, monotonic time it was entered)
        self.accept_resume_at = None  # while out of descriptors: when accepting is tried again
        self.accept_failing = False
        self.refusals_logged_at = None
        self.socket_file = SocketFile(path)
        try:
            self.listener = self.socket_file.bind()
        except BaseException:
            self.socket_file.remove()
            raise
        self.readers[self.listener.fileno()] = self.accept
        log("supervisor", f"control socket {path} (python3 supervisor.py ctl --control-socket {path} status)")

    def close(self) -> None:
        for connection in list(self.connections.values()):
            connection.close()
        self.readers.pop(self.listener.fileno(), None)
        self.listener.close()
        self.socket_file.remove()

    # Clients

    def accept(self) -> None:
        for _ in range(CONTROL_ACCEPTS_PER_TURN):
            try:
                connection, _ = self.listener.accept()
            except (BlockingIOError, InterruptedError):
                if self.accept_failing:  # every waiting client was taken
                    self.accept_failing = False
                    log("supervisor", "control socket: accepting clients again")
                return
            except OSError as exc:
                if exc.errno in ACCEPT_OUT_OF_RESOURCES:
                    self.pause_accepting(exc)
                return  # otherwise that client is gone already
            self.admit(connection)

    def pause_accepting(self, exc: OSError) -> None:
        """Out of descriptors: stop watching the socket for CONTROL_ACCEPT_BACKOFF_S (its queue keeps the
        clients waiting), rather than being woken at once again for a client that cannot be accepted."""
        self.readers.pop(self.listener.fileno(), None)
        self.accept_resume_at = time.monotonic() + CONTROL_ACCEPT_BACKOFF_S
        if not self.accept_failing:
            self.accept_failing = True
            log(
                "supervisor",
                f"control socket: cannot accept a client ({exc.strerror}); trying again every "
                f"{CONTROL_ACCEPT_BACKOFF_S} s",
            )

    def admit(self, connection) -> None:
        try:
            pid, uid, _ = peer_credentials(connection)
        except OSError:
            connection.close()
            return
        if not may_control(uid):
            self.note_refusal(uid, pid)
            refuse(
                connection, "forbidden", f"uid {uid} may not use this control socket (only uid {os.geteuid()} and root)"
            )
        elif len(self.connections) >= self.clients_max:
            refuse(connection, "busy", f"too many control clients ({self.clients_max}); try again later")
        else:
            client = ControlConnection(self, connection, pid)
            self.connections[client.fd] = client

    def note_refusal(self, uid: int, pid: int) -> None:
        now = time.monotonic()
        if self.refusals_logged_at is None or now - self.refusals_logged_at >= CONTROL_REFUSAL_LOG_S:
            self.refusals_logged_at = now
            log("supervisor", f"control socket: refused a client of uid {uid} (pid {pid})")

    def drop_unread(self, connection, size: int) -> None:
        log(
            "supervisor",
            f"control socket: dropped a client (pid {connection.pid}) that left {size} bytes of replies unread "
            f"(at most {CONTROL_OUTPUT_LIMIT_BYTES} a client, {CONTROL_OUTPUT_TOTAL_BYTES} in all)",
        )
        connection.close()

    def turn_ends_at(self) -> float:
        """When request lines must wait for the next turn of the loop: CONTROL_TURN_S after it woke."""
        return self.supervisor.poller.woke_at + CONTROL_TURN_S

    def forget(self, connection) -> None:
        self.connections.pop(connection.fd, None)

    # Requests

    def on_request(self, connection, line: bytes) -> None:
        try:
            request = parse_request(line)
        except RequestError as exc:
            connection.send(refusal("bad_request", str(exc)))
            return
        reply = self.handle(connection, request)
        if reply is None:
            connection.waiting += request["command"] in ("restart", "stop", "reload")
        else:
            connection.send(reply)

    def handle(self, connection, request):
        """The reply to `request`, or None when it comes later (a stop or restart in progress, or none at all
        for `logs` that sent its own)."""
        command = request["command"]
        if command == "status":
            return {"ok": True, **self.status()}
        if command == "reload":
            if self.supervisor.stopping:
                return refusal("stopping", "the robot is stopping")
            if self.pending or self.reloading is not None:
                return refusal("conflict", "a stop, restart or reload is under way: try again once it is done")
            return begin_reload(self, connection, request["path"])
        node = next((n for n in self.supervisor.nodes if n.name == request["node"]), None)
        if node is None:
            return refusal("not_found", f"no node named {request['node']!r:.80}")
        if command == "logs":
            return self.logs(connection, node, request)
        if self.supervisor.stopping:
            return refusal("stopping", "the robot is stopping")
        if self.reloading is not None:
            return refusal("conflict", "a reload is under way: try again once it is done")
        if node.name in self.pending:
            return refusal("conflict", f"{node.name} is already being stopped or restarted")
        if command == "start":
            if node.alive():
                return refusal("conflict", f"{node.name} is already {node.state}")
            self.start(node)
            return self.action_reply(node)
        if not node.alive():
            if command == "restart":
                node.manual_restarts += 1
                self.start(node)
            elif node.state == "backoff":  # nothing runs, a restart is due: it is called off
                node.restart_at = None
                node.stop_requested = True
                node.state = "stopped"
            else:  # nothing runs and nothing is due: stopped, finished or failed
                return refusal("conflict", f"{node.name} is already {node.state}")
            return self.action_reply(node)
        then = self.start_again if command == "restart" else None
        self.stop_node(node, f"{command} requested over the control socket", [connection], then)
        return None

    def stop_node(self, node, reason: str, waiters=(), then=None) -> None:
        """Stop `node` with its cascade (SIGINT now, SIGTERM and SIGKILL after the grace periods); once nothing
        it started is left, call `then(node)` when given and answer the `waiters`."""
        self.pending[node.name] = {
            "stage": "SIGINT",
            "deadline": time.monotonic() + self.supervisor.build.sigint_grace_s,
            "then": then,
            "waiters": list(waiters),
        }
        node.stop_requested = True
        node.state = "stopping"
        node.sigint_sent(time.monotonic())
        log(node.name, f"{reason}: sending SIGINT")
        self.supervisor.signal_node(node, signal.SIGINT)

    def start_again(self, node) -> None:
        """The second half of a restart asked for over the socket."""
        if not self.supervisor.stopping:
            node.manual_restarts += 1
            self.start(node)

    def start(self, node) -> None:
        node.stop_requested = False
        node.restart_at = None
        self.supervisor.launch(node)

    def action_reply(self, node) -> dict:
        return {"ok": True, "node": node.name, "state": node.state, "pid": node.pid}

    def status(self) -> dict:
        """{"robot", "run": {"id", "started", "build", "built"}, "nodes": [{"name", "state", "pid", "restarts" (by
        the restart policy), "manual_restarts" (asked for here), "ready", "since_s"}]}; a host's supervisor of a
        robot on several adds "host", and "discovery" when there is a Discovery Server (discovery_report.py)."""
        now = time.monotonic()
        self.note_states(now)
        discovery = self.supervisor.readiness.discovery
        return {
            "robot": ROBOT["name"],
            **({"host": ROBOT["host"]} if ROBOT.get("host") else {}),
            **({"discovery": discovery.as_dict(now)} if discovery is not None else {}),
            "run": self.supervisor.run_mark.as_dict(),
            "nodes": [
                {
                    "name": node.name,
                    "state": node.state,
                    "pid": node.pid,
                    "restarts": node.restarts,
                    "manual_restarts": node.manual_restarts,
                    "ready": node.ready,
                    "since_s": round(now - self.since[node.name][1], 3),
                }
                for node in self.supervisor.nodes
            ],
        }

    def logs(self, connection, node, request) -> None:
        node_log = self.supervisor.logs.get(node.name)
        if node_log is None:
            connection.send(refusal("not_found", f"the output of {node.name} is not kept (no log directory)"))
            return None
        connection.send({"ok": True, "lines": node_log.tail(request["lines"], request["all"])})
        if request["follow"] and not connection.closed:
            connection.follow(node_log)
        return None

    # The loop's part

    def note_states(self, now: float) -> None:
        for node in self.supervisor.nodes:
            if self.since.get(node.name, ("",))[0] != node.state:
                self.since[node.name] = (node.state, now)

    def deadline(self):
        """The next moment poll() must run (a stop's signal escalation, accepting again, lines left), or None."""
        moments = [item["deadline"] for item in self.pending.values()]
        if self.accept_resume_at is not None:
            moments.append(self.accept_resume_at)
        if self.backlog:
            moments.append(time.monotonic())
        return min(moments, default=None)

    def poll(self) -> None:
        """Resume accepting; handle lines left; finish stops and restarts whose node is gone, escalate those
        past their grace."""
        now = time.monotonic()
        if self.accept_resume_at is not None and now >= self.accept_resume_at:
            self.accept_resume_at = None
            self.readers[self.listener.fileno()] = self.accept
        for index, connection in enumerate(list(self.backlog.values())):
            if index and time.monotonic() >= self.turn_ends_at():
                break  # the first always gets a line: lines left are handled, however busy the socket
            del self.backlog[connection.fd]
            connection.handle_lines(at_least_one=not index)
        for node in list(self.supervisor.nodes):  # a reload's `then` may take a node out of the list
            item = self.pending.get(node.name)
            if item is None:
                continue
            if not node.alive():
                del self.pending[node.name]
                node.state = "stopped"
                if item["then"] is not None:
                    item["then"](node)
                for connection in item["waiters"]:
                    connection.answer(self.action_reply(node))
            elif now >= item["deadline"] and item["stage"] == "SIGINT" and node.stop_held(now):
                item["deadline"] = node.stop_extended_until  # it asked for more time to stop cleanly
            elif now >= item["deadline"]:
                grace = self.supervisor.build.sigterm_grace_s
                stage, number = (
                    ("SIGTERM", signal.SIGTERM) if item["stage"] == "SIGINT" else ("SIGKILL", signal.SIGKILL)
                )
                log(node.name, f"still running: escalating to {stage}")
                item.update(stage=stage, deadline=now + grace)
                self.supervisor.signal_node(node, number)
        self.note_states(now)


def refuse(connection, kind: str, error: str) -> None:
    """Send one error line to a client not admitted (it fits any socket buffer), then close it."""
    import json

    try:
        connection.setblocking(False)
        connection.send(json.dumps(refusal(kind, error)).encode() + b"\n", socket.MSG_NOSIGNAL)
    except OSError:
        pass
    close_quietly(connection)
