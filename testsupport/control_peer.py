"""A process manager that serves the supervisor's control protocol (CONTROL.md) for dashboard tests.

It runs real commands as child processes, writes each one's output to `<log dir>/<name>.log`, and
answers `status`, `restart`/`stop`/`start` and `logs` on a Unix socket (0600), one JSON line each way.
"""

import json
import os
import signal
import socketserver
import subprocess
import threading
import time
from pathlib import Path

STOP_TIMEOUT_S = 5.0


class _Child:
    def __init__(self, name: str, argv: list[str], env: dict, log_path: Path):
        self.name, self.argv, self.env, self.log_path = name, argv, env, log_path
        self.process: subprocess.Popen | None = None
        self.state = "pending"
        self.restarts = 0
        self.since = time.monotonic()

    def start(self) -> None:
        with open(self.log_path, "ab") as log:
            self.process = subprocess.Popen(self.argv, env=self.env, stdout=log, stderr=subprocess.STDOUT,
                                            start_new_session=True)
        self._enter("running")

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self._enter("stopping")
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(STOP_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self._enter("stopped")

    def _enter(self, state: str) -> None:
        self.state, self.since = state, time.monotonic()

    def status(self) -> dict:
        if self.state == "running" and self.process.poll() is not None:
            self._enter("finished" if self.process.returncode == 0 else "failed")
        running = self.state == "running"
        return {"name": self.name, "state": self.state, "pid": self.process.pid if running else None,
                "restarts": self.restarts, "ready": running, "since_s": round(time.monotonic() - self.since, 3)}


class ControlPeer:
    """`children` maps a name to (argv, env); all are started at once and stopped by `close()`."""

    def __init__(self, robot: str, socket_path: Path, log_dir: Path, children: dict[str, tuple[list[str], dict]]):
        self.robot = robot
        self.lock = threading.Lock()
        self.children = {name: _Child(name, argv, env, log_dir / f"{name}.log") for name, (argv, env) in children.items()}
        for child in self.children.values():
            child.start()
        peer = self

        class Handler(socketserver.StreamRequestHandler):
            def handle(self):
                for line in self.rfile:
                    self.wfile.write(json.dumps(peer.answer(json.loads(line))).encode() + b"\n")

        self.server = socketserver.ThreadingUnixStreamServer(str(socket_path), Handler)
        os.chmod(socket_path, 0o600)
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def answer(self, request: dict) -> dict:
        command = request.get("command")
        with self.lock:
            if command == "status":
                return {"ok": True, "robot": self.robot, "nodes": [c.status() for c in self.children.values()]}
            child = self.children.get(request.get("node"))
            if child is None:
                return {"ok": False, "error": f"no node named {request.get('node')!r}"}
            if command == "logs":
                lines = child.log_path.read_text(errors="replace").splitlines()
                return {"ok": True, "lines": lines[-int(request.get("lines", 100)):]}
            if command in ("restart", "stop"):
                child.stop()
            if command in ("restart", "start"):
                child.restarts += command == "restart"
                child.start()
            if command not in ("restart", "stop", "start"):
                return {"ok": False, "error": f"unknown command {command!r}"}
            status = child.status()
            return {"ok": True, "node": child.name, "state": status["state"], "pid": status["pid"]}

    def pid(self, name: str) -> int | None:
        with self.lock:
            return self.children[name].status()["pid"]

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()
        for child in self.children.values():
            child.stop()
