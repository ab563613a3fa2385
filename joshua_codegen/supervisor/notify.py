"""Readiness: the sd_notify socket nodes send READY=1 to, the ready flag of each node, and the "ready" lines."""

import os
import socket
import struct
import time

from joshua_codegen.supervisor.common import START, log
from joshua_codegen.supervisor.discovery_report import DISCOVERY_FIELD, DiscoveryReport
from joshua_codegen.supervisor.policy import READY_TIMEOUT_S

NOTIFY_VARIABLES = ("NOTIFY_SOCKET", "WATCHDOG_USEC", "WATCHDOG_PID")
NOTIFY_DATAGRAM_MAX = 4096
EXTEND_FIELD = "EXTEND_TIMEOUT_USEC"  # a stopping node asks for more time before its SIGTERM
UCRED = struct.Struct("3i")  # pid, uid, gid


def notify_fields(data: bytes) -> dict[str, str]:
    """The KEY=VALUE lines of one notification datagram."""
    fields = {}
    for line in data.decode("utf-8", "replace").splitlines():
        key, equals, value = line.partition("=")
        if equals:
            fields[key] = value
    return fields


def notify_upstream(address: str, text: str) -> None:
    """Send one notification to the manager that runs the supervisor itself (best effort)."""
    target = "\0" + address[1:] if address.startswith("@") else address
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM | socket.SOCK_CLOEXEC) as sender:
            sender.sendto(text.encode(), target)
    except OSError:
        pass


class Readiness:
    """Receives the nodes' notifications and keeps each node's `ready` flag.

    One Unix datagram socket in the abstract namespace (`@joshua-notify-<robot>-<supervisor pid>`),
    handed to every node as NOTIFY_SOCKET. SO_PASSCRED makes the kernel attach the sender's pid to each
    datagram, so a message counts only when it comes from a node's main process (systemd's
    NotifyAccess=main). A node is ready when it sends READY=1 (the Python runtime and the C++ binaries
    do); a CUSTOM program when it starts (it need not speak the protocol). A node not ready READY_TIMEOUT_S after its start gets one warning and keeps
    running. When every running node is ready, the supervisor logs "ready: N of N nodes ready" and,
    when it runs under systemd itself (Type=notify), passes READY=1 on to its own NOTIFY_SOCKET.
    WATCHDOG=1 is not enforced here (systemd's WatchdogSec= does that). A stopping node that needs longer than
    the SIGINT grace to stop cleanly sends EXTEND_TIMEOUT_USEC=N (as systemd takes it while a unit stops): its
    SIGTERM waits until N µs after its last such message, at most STOP_EXTENSION_MAX_S after its SIGINT.
    """

    def __init__(self, nodes, robot_name):
        self.nodes = nodes
        self.upstream = os.environ.get("NOTIFY_SOCKET", "")
        self.all_ready = False
        self.discovery = DiscoveryReport.of_robot()  # what the host's agent says of the Discovery Server
        self.socket = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM | socket.SOCK_CLOEXEC | socket.SOCK_NONBLOCK)
        self.socket.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 1)
        name = f"joshua-notify-{robot_name}-{os.getpid()}"[:100]
        self.socket.bind("\0" + name)
        self.address = "@" + name
        for node in nodes:
            self.adopt(node)

    def adopt(self, node):
        """Give a node (of the robot from the start, or of a reload) this socket in place of any of its own."""
        for variable in NOTIFY_VARIABLES:
            node.environment.pop(variable, None)
        node.environment["NOTIFY_SOCKET"] = self.address

    def fileno(self):
        return self.socket.fileno()

    def on_launch(self, node, now):
        """A node just started: runtime nodes (Python or C++) are ready once they say so; a CUSTOM
        program, which may not speak sd_notify, is ready now."""
        silent = {"custom": "a CUSTOM program"}.get(node.backend)
        node.stop_extension_limit = node.stop_extended_until = None
        node.ready = silent is not None
        node.ready_deadline = None if node.ready else now + READY_TIMEOUT_S
        if node.ready:
            self.on_ready(node, now, f"{silent}: ready when started")

    def on_exit(self, node):
        node.ready = False
        node.ready_deadline = None
        self.all_ready = False
        if self.discovery is not None:
            self.discovery.forget(node, time.monotonic())

    def receive(self, node_of_pid, now):
        """Read every pending datagram; `node_of_pid(pid)` names the node whose main process sent it."""
        while True:
            try:
                data, ancillary, _, _ = self.socket.recvmsg(NOTIFY_DATAGRAM_MAX, socket.CMSG_SPACE(UCRED.size))
            except (BlockingIOError, InterruptedError):
                return
            pid = None
            for level, kind, payload in ancillary:
                if level == socket.SOL_SOCKET and kind == socket.SCM_CREDENTIALS and len(payload) >= UCRED.size:
                    pid = UCRED.unpack_from(payload)[0]
            node = node_of_pid(pid) if pid is not None else None
            if node is None:
                continue  # not a node's main process: ignored, like NotifyAccess=main
            fields = notify_fields(data)
            if "STATUS" in fields:
                node.status_text = fields["STATUS"]
            if DISCOVERY_FIELD in fields and self.discovery is not None:
                self.discovery.record(node, fields[DISCOVERY_FIELD], node.status_text, now)
            if fields.get("READY") == "1" and not node.ready:
                node.ready = True
                node.ready_deadline = None
                self.on_ready(node, now, node.status_text)
            if fields.get(EXTEND_FIELD, "").isdigit():
                self.extend_stop(node, int(fields[EXTEND_FIELD]) / 1e6, now)

    def extend_stop(self, node, seconds, now):
        """A node asks for `seconds` more before SIGTERM; only while it is stopping since a SIGINT."""
        if node.stop_extension_limit is None or node.state != "stopping":
            return
        first = node.stop_extended_until is None
        node.stop_extended_until = min(now + seconds, node.stop_extension_limit)
        if first:
            why = f" ({node.status_text})" if node.status_text else ""
            log(node.name, f"stopping takes longer: it asks for {seconds:g} s more{why}")

    def on_ready(self, node, now, status):
        log(node.name, f"ready after {now - node.started_at:.2f} s" + (f": {status}" if status else ""))

    def check_all(self, now):
        """Log the robot's ready line when every running node is ready and none waits to start (or, after a reload,
        to be stopped)."""
        if self.all_ready:
            return
        if any(
            node.state in ("pending", "backoff", "stopping") or (node.state == "running" and not node.ready)
            for node in self.nodes
        ):
            return
        ready = sum(node.ready for node in self.nodes)
        if not ready:
            return
        self.all_ready = True
        others = len(self.nodes) - ready
        log(
            "supervisor",
            f"ready: {ready} of {len(self.nodes)} nodes ready ({now - START:.2f} s after start)"
            + (f"; {others} not running" if others else ""),
        )
        if self.upstream:
            notify_upstream(self.upstream, f"READY=1\nSTATUS={ready} of {len(self.nodes)} nodes ready")

    def next_deadline(self):
        deadlines = [node.ready_deadline for node in self.nodes if node.ready_deadline is not None]
        return min(deadlines) if deadlines else None

    def on_timer(self, now, stopping):
        if not stopping:
            self.check_all(now)
        for node in self.nodes:
            if node.ready_deadline is not None and now >= node.ready_deadline:
                node.ready_deadline = None
                if node.state == "running" and not node.ready:
                    log(
                        node.name,
                        f"warning: not ready {READY_TIMEOUT_S:g} s after its start (no READY=1 "
                        "yet); it keeps running and the robot is not ready",
                    )
