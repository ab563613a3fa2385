"""The control socket: status, restart / stop / start of one node and its log, one JSON line each way."""

import json
import os
import signal
import socket
import time

from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.robot import ROBOT, SIGINT_GRACE_S, SIGTERM_GRACE_S

CONTROL_SOCKET_VARIABLE = "JOSHUA_CONTROL_SOCKET"  # told to every node, so a dashboard finds the socket
CONTROL_REQUEST_LIMIT = 65536  # longest request line accepted
CONTROL_SEND_TIMEOUT_S = 1.0  # a client that does not read its replies for this long is dropped
LOG_LINES_DEFAULT = 100


def default_control_socket(robot: str) -> str:
    """$XDG_RUNTIME_DIR/joshua/<robot>.sock, else /tmp/joshua-<uid>/<robot>.sock."""
    runtime_dir = os.environ.get("XDG_RUNTIME_DIR")
    directory = os.path.join(runtime_dir, "joshua") if runtime_dir else f"/tmp/joshua-{os.getuid()}"
    return os.path.join(directory, f"{robot}.sock")


class ControlClient:
    """One connection: buffers request bytes, writes reply lines, may follow a node's log."""

    def __init__(self, connection):
        self.connection = connection
        self.connection.settimeout(CONTROL_SEND_TIMEOUT_S)
        self.buffer = b""
        self.following = None  # (NodeLog, listener) while `logs -f` runs
        self.closed = False

    def send(self, reply: dict) -> None:
        if self.closed:
            return
        try:
            self.connection.sendall(json.dumps(reply).encode() + b"\n")
        except OSError:
            self.close()

    def close(self) -> None:
        if self.following is not None:
            node_log, listener = self.following
            if listener in node_log.listeners:
                node_log.listeners.remove(listener)
            self.following = None
        if not self.closed:
            self.closed = True
            self.connection.close()


class ControlPlane:
    """Serves the socket for a Supervisor: registers its descriptors in `supervisor.readers`, and is
    polled by the loop (`poll`) to finish node stops and restarts and to escalate their signals.

    Requests: {"command": "status"}, {"command": "restart"|"stop"|"start", "node": NAME},
    {"command": "logs", "node": NAME, "lines": N, "follow": false|true}. Replies: {"ok": true, ...}
    or {"ok": false, "error": "one line"}; a stop or restart is answered once it has been done (a
    stop: SIGINT, SIGTERM after sigint_grace_s, SIGKILL after sigterm_grace_s more). The socket is a
    Unix stream socket of mode 0600 in a directory of mode 0700.
    """

    def __init__(self, supervisor, path: str):
        self.supervisor = supervisor
        self.path = path
        self.clients = {}  # fd -> ControlClient
        self.pending = {}  # node name -> {"stage", "deadline", "then_start", "waiters": [(client, command)]}
        self.since = {}  # node name -> (state, monotonic time it was entered)
        directory = os.path.dirname(path)
        os.makedirs(directory, mode=0o700, exist_ok=True)
        if os.path.exists(path):
            probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            try:
                probe.connect(path)
            except OSError:
                os.unlink(path)  # left by a supervisor that was killed
            else:
                raise OSError(f"another supervisor serves {path}")
            finally:
                probe.close()
        self.listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        old_mask = os.umask(0o177)
        try:
            self.listener.bind(path)
        finally:
            os.umask(old_mask)
        os.chmod(path, 0o600)
        self.listener.listen(16)
        self.listener.setblocking(False)
        supervisor.readers[self.listener.fileno()] = self.accept
        log("supervisor", f"control socket {path} (python3 supervisor.py ctl --control-socket {path} status)")

    def close(self) -> None:
        for client in list(self.clients.values()):
            client.close()
        self.supervisor.readers.pop(self.listener.fileno(), None)
        self.listener.close()
        try:
            os.unlink(self.path)
        except OSError:
            pass

    def accept(self) -> None:
        try:
            connection, _ = self.listener.accept()
        except OSError:
            return
        client = ControlClient(connection)
        fd = connection.fileno()
        self.clients[fd] = client
        self.supervisor.readers[fd] = lambda: self.receive(fd)

    def drop(self, fd: int) -> None:
        self.supervisor.readers.pop(fd, None)
        client = self.clients.pop(fd, None)
        if client is not None:
            client.close()

    def receive(self, fd: int) -> None:
        client = self.clients[fd]
        try:
            data = client.connection.recv(CONTROL_REQUEST_LIMIT)
        except OSError:
            data = b""
        if not data or len(client.buffer) + len(data) > CONTROL_REQUEST_LIMIT:
            self.drop(fd)
            return
        client.buffer += data
        while b"\n" in client.buffer and not client.closed:
            line, client.buffer = client.buffer.split(b"\n", 1)
            try:
                request = json.loads(line)
            except ValueError as exc:
                request = f"not JSON ({exc})"
            if not isinstance(request, dict):
                client.send({"ok": False, "error": f"a request is one JSON object per line, got {request!r:.80}"})
                continue
            reply = self.handle(client, request)
            if reply is not None:
                client.send(reply)
        if client.closed:
            self.drop(fd)

    # Requests

    def handle(self, client, request):
        """The reply to `request`, or None when it comes later (a stop or restart in progress)."""
        command = request.get("command")
        if command == "status":
            return {"ok": True, **self.status()}
        node = next((n for n in self.supervisor.nodes if n.name == request.get("node")), None)
        if command not in ("restart", "stop", "start", "logs"):
            return {"ok": False, "error": f"unknown command {command!r} (status, restart, stop, start, logs)"}
        if node is None:
            return {"ok": False, "error": f"no node named {request.get('node')!r}"}
        if command == "logs":
            return self.logs(client, node, request)
        if self.supervisor.stopping:
            return {"ok": False, "error": "the robot is stopping"}
        if node.name in self.pending:
            return {"ok": False, "error": f"{node.name} is already being stopped or restarted"}
        if command == "start":
            if node.alive():
                return {"ok": False, "error": f"{node.name} is already {node.state}"}
            self.start(node)
            return self.action_reply(node)
        if not node.alive():
            if command == "stop":
                node.restart_at = None
                node.state = "stopped"
                return self.action_reply(node)
            self.start(node)
            return self.action_reply(node)
        self.pending[node.name] = {
            "stage": "SIGINT",
            "deadline": time.monotonic() + SIGINT_GRACE_S,
            "then_start": command == "restart",
            "waiters": [client],
        }
        node.stop_requested = True
        node.state = "stopping"
        log(node.name, f"{command} requested over the control socket: sending SIGINT")
        self.supervisor.signal_node(node, signal.SIGINT)
        return None

    def start(self, node) -> None:
        node.stop_requested = False
        node.restart_at = None
        self.supervisor.launch(node)

    def action_reply(self, node) -> dict:
        return {"ok": True, "node": node.name, "state": node.state, "pid": node.pid}

    def status(self) -> dict:
        now = time.monotonic()
        self.note_states(now)
        return {
            "robot": ROBOT["name"],
            "nodes": [
                {
                    "name": node.name,
                    "state": node.state,
                    "pid": node.pid,
                    "restarts": node.restarts,
                    "ready": node.ready,
                    "since_s": round(now - self.since[node.name][1], 3),
                }
                for node in self.supervisor.nodes
            ],
        }

    def logs(self, client, node, request) -> dict | None:
        try:
            count = int(request.get("lines", LOG_LINES_DEFAULT))
        except (TypeError, ValueError):
            return {"ok": False, "error": "lines must be a whole number"}
        node_log = self.supervisor.logs[node.name]
        client.send({"ok": True, "lines": node_log.tail(count)})
        if request.get("follow"):

            def listener(line, client=client):
                client.send({"line": line})

            node_log.listeners.append(listener)
            client.following = (node_log, listener)
        return None

    # The loop's part

    def note_states(self, now: float) -> None:
        for node in self.supervisor.nodes:
            if self.since.get(node.name, ("",))[0] != node.state:
                self.since[node.name] = (node.state, now)

    def deadline(self):
        """The next moment poll() must run (a stop's signal escalation), or None."""
        return min((item["deadline"] for item in self.pending.values()), default=None)

    def poll(self) -> None:
        """Finish stops and restarts whose node is gone; escalate those past their grace."""
        now = time.monotonic()
        for node in self.supervisor.nodes:
            item = self.pending.get(node.name)
            if item is None:
                continue
            if not node.alive():
                del self.pending[node.name]
                node.state = "stopped"
                if item["then_start"] and not self.supervisor.stopping:
                    node.restarts += 1
                    self.start(node)
                for client in item["waiters"]:
                    client.send(self.action_reply(node))
            elif now >= item["deadline"]:
                stage, number, grace = (
                    ("SIGTERM", signal.SIGTERM, SIGTERM_GRACE_S)
                    if item["stage"] == "SIGINT"
                    else ("SIGKILL", signal.SIGKILL, SIGTERM_GRACE_S)
                )
                log(node.name, f"still running: escalating to {stage}")
                item.update(stage=stage, deadline=now + grace)
                self.supervisor.signal_node(node, number)
        self.note_states(now)
