"""A running robot for the dashboard tests: a build by joshuac, its nodes under a control-socket peer,
the dashboard server, and Debian's headless Chromium driven by Playwright."""

import json
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

from testsupport.control_peer import ControlPeer
from testsupport.joshuac_cli import joshuac

CHROMIUM = "/usr/bin/chromium-headless-shell"
CHROMIUM_FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                  "--disable-sync", "--no-first-run"]
SERVER_START_TIMEOUT_S = 60.0
ARTIFACTS = Path(__file__).resolve().parents[3] / "test-artifacts" / "dashboard"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def build(description: str, directory: Path) -> Path:
    """Build a description text with joshuac into `directory`/out; return the manifest's path."""
    source = directory / "robot.pbtxt"
    source.write_text(description)
    result = joshuac("build", source, "-o", directory / "out")
    assert result.returncode == 0, result.stderr
    return directory / "out" / "manifest.json"


def get_json(url: str, token: str | None = None):
    request = urllib.request.Request(url, headers={"Authorization": f"Bearer {token}"} if token else {})
    with urllib.request.urlopen(request, timeout=10) as response:
        return json.loads(response.read())


def wait_for_server(url: str, process: subprocess.Popen, token: str | None = None) -> None:
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise AssertionError(f"the server exited with {process.returncode}: {process.stderr.read()}")
        try:
            get_json(url, token)
            return
        except OSError:
            time.sleep(0.2)
    raise AssertionError(f"{url} did not answer within {SERVER_START_TIMEOUT_S:g} s")


def stop(process: subprocess.Popen) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


@contextmanager
def running_robot(manifest: Path, env: dict, run_nodes: list[str], workdir: Path, *extra_args: str):
    """The robot's nodes `run_nodes` under a ControlPeer, and its dashboard; yields (url, peer, server)."""
    processes = {p["name"]: p for p in json.loads(manifest.read_text())["processes"]}
    robot = json.loads(manifest.read_text())["robot"]["name"]
    logs = workdir / "logs"
    logs.mkdir(exist_ok=True)
    control_socket = workdir / "control.sock"
    peer = ControlPeer(robot, control_socket, logs, {
        name: ([sys.executable, str(manifest.parent / processes[name]["entrypoint"])], env) for name in run_nodes
    })
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.dashboard", "--manifest", str(manifest), "--control-socket",
         str(control_socket), "--port", str(port), *extra_args],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        wait_for_server(f"{url}/api/robot", server)
        yield url, peer, server
    finally:
        stop(server)
        peer.close()


@contextmanager
def browser():
    """Debian's headless Chromium under Playwright (never a downloaded browser)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        instance = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            yield instance
        finally:
            instance.close()


def screenshot(page, name: str) -> Path:
    """Write a full-page screenshot as a test artifact under test-artifacts/dashboard/."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    path = ARTIFACTS / f"{name}.png"
    page.screenshot(path=str(path), full_page=True)
    return path
