"""A running robot for the dashboard tests: a build by joshuac, its nodes under a control-socket peer,
the dashboard server, and Debian's headless Chromium driven by Playwright.

Every page opened through `browser()` is watched: an uncaught exception or a console error in it fails
the test (at the end of the `with` block, or at `errors.check()`), unless the test said it provokes
that error on purpose (`errors.expect(PATTERN)`). Screenshots go to test-artifacts/dashboard/ at the
root of the checkout (ignored by git, kept between runs), one file per name.
"""

import itertools
import json
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from contextlib import ExitStack, contextmanager
from pathlib import Path

from api_contract import check_event, check_reply

from joshua_core.dashboard_token import token_path
from testsupport.joshuac_cli import joshuac

CHROMIUM = "/usr/bin/chromium-headless-shell"
CHROMIUM_FLAGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
SERVER_START_TIMEOUT_S = 60.0
ARTIFACTS = Path(__file__).resolve().parents[3] / "test-artifacts" / "dashboard"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def build(description: str, directory: Path, overrides=()) -> Path:
    """Build a description text with joshuac (and `--set` each of `overrides`) into `directory`/out;
    return the manifest's path."""
    source = directory / "robot.pbtxt"
    source.write_text(description)
    result = joshuac("build", source, "-o", directory / "out", *[arg for item in overrides for arg in ("--set", item)])
    assert result.returncode == 0, result.stderr
    return directory / "out" / "manifest.json"


def get_json(url: str, token: str | None = None):
    """The JSON reply to a GET of `url`; a reply of a route under /api/ is checked against the API schema."""
    request = urllib.request.Request(url, headers={"Authorization": f"Bearer {token}"} if token else {})
    with urllib.request.urlopen(request, timeout=10) as response:
        body = json.loads(response.read())
        path = urllib.parse.urlsplit(url).path
        if path.startswith("/api/"):
            check_reply("GET", path, response.status, body)
        return body


EVENTS_TIMEOUT_S = 30
MAX_EVENT_PROBLEMS = 5  # the first events that do not match the API schema, kept to be shown


class EventReader:
    """The dashboard's /api/events, read line by line in a thread until the server ends it. Every event is
    checked against the API schema as it arrives (`check` fails on the first that did not match); the
    events themselves are kept only when `keep` (a robot's camera frames add up over a long test)."""

    def __init__(self, url: str, token: str, keep: bool = True):
        request = urllib.request.Request(url + "/api/events", headers={"Authorization": f"Bearer {token}"})
        self.response = urllib.request.urlopen(request, timeout=EVENTS_TIMEOUT_S)
        self.keep = keep
        self.events: list[tuple[str, dict, float]] = []  # (kind, data, local time it arrived), when kept
        self.seen: set[str] = set()  # the kinds of every event read
        self.problems: list[str] = []
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        kind = None
        try:
            for raw in self.response:
                line = raw.decode().rstrip("\n")
                if line.startswith("event: "):
                    kind = line[len("event: ") :]
                elif line.startswith("data: ") and kind:
                    self._note(kind, json.loads(line[len("data: ") :]))
        except (OSError, ValueError):
            pass

    def _note(self, kind: str, data: dict) -> None:
        try:
            check_event(kind, data)
            problem = None
        except AssertionError as exc:
            problem = str(exc)
        with self.lock:
            self.seen.add(kind)
            if problem and len(self.problems) < MAX_EVENT_PROBLEMS:
                self.problems.append(problem)
            if self.keep:
                self.events.append((kind, data, time.time()))

    def kinds(self) -> set[str]:
        """The kinds of the events read so far."""
        with self.lock:
            return set(self.seen)

    def check(self) -> None:
        """Every event read so far is what the API schema says its kind carries."""
        with self.lock:
            problems = list(self.problems)
        assert not problems, "\n".join(problems)

    def wait_for_kind(self, kind: str) -> None:
        """Wait for an event of `kind`; every event read until then matches the API schema."""
        deadline = time.monotonic() + EVENTS_TIMEOUT_S
        while kind not in self.kinds():
            assert time.monotonic() < deadline, f"no {kind} event within {EVENTS_TIMEOUT_S} s: {sorted(self.kinds())}"
            time.sleep(0.02)
        self.check()

    def wait_for(self, condition, what: str):
        """The first kept event that meets `condition(kind, data)`; every event read until then matches the API
        schema."""
        deadline = time.monotonic() + EVENTS_TIMEOUT_S
        while time.monotonic() < deadline:
            self.check()
            with self.lock:
                found = [event for event in self.events if condition(*event[:2])]
            if found:
                return found[0]
            time.sleep(0.02)
        raise AssertionError(f"no {what} event within {EVENTS_TIMEOUT_S} s: {[e[0] for e in self.events]}")


def dashboard_token(control_socket: Path) -> str:
    """The access token of the dashboard of the robot whose supervisor serves `control_socket`."""
    return token_path(control_socket).read_text().strip()


def wait_for_server(url: str, process: subprocess.Popen, output: Path) -> None:
    """Wait until `url` answers, whatever the status (401 without a token too); `output` is where the
    process writes (shown when it fails)."""
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise AssertionError(f"{process.args[1]} exited with {process.returncode}:\n{output.read_text()}")
        try:
            get_json(url)
            return
        except urllib.error.HTTPError:
            return
        except OSError:
            time.sleep(0.2)
    raise AssertionError(f"{url} did not answer within {SERVER_START_TIMEOUT_S:g} s:\n{output.read_text()}")


def stop(process: subprocess.Popen) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def control_request(control_socket: Path, request: dict) -> dict:
    """One request to a supervisor's control socket, and its reply."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as connection:
        connection.settimeout(30)
        connection.connect(str(control_socket))
        connection.sendall(json.dumps(request).encode() + b"\n")
        return json.loads(connection.makefile("rb").readline())


def node_pid(control_socket: Path, name: str) -> int | None:
    nodes = control_request(control_socket, {"command": "status"})["nodes"]
    return next(node["pid"] for node in nodes if node["name"] == name)


@contextmanager
def running_robot(description: str, directory: Path, env: dict, dashboard_port: int | None = None, overrides=()):
    """The robot's generated supervisor.py, run with a control socket in `directory` (the dashboard's
    token file beside it); waits for its dashboard at `dashboard_port` when given. `overrides` are
    joshuac's `--set` values. Yields the control socket's path."""
    manifest = build(description, directory, overrides)
    control_socket = directory / "run" / "robot.sock"
    output = directory / "supervisor.log"
    with open(output, "w") as log:
        supervisor = subprocess.Popen(
            [
                sys.executable,
                str(manifest.parent / "supervisor.py"),
                "--python",
                sys.executable,
                "--control-socket",
                str(control_socket),
                "--log-dir",
                str(directory / "logs"),
            ],
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    try:
        if dashboard_port is not None:
            wait_for_server(f"http://127.0.0.1:{dashboard_port}/api/robot", supervisor, output)
        else:
            deadline = time.monotonic() + SERVER_START_TIMEOUT_S
            while not control_socket.exists():
                assert supervisor.poll() is None and time.monotonic() < deadline, "the supervisor did not start"
                time.sleep(0.05)
        yield control_socket
    finally:
        stop(supervisor)


class PageErrors:
    """The uncaught exceptions and console errors of the pages a test opens."""

    def __init__(self):
        self.pages = []
        self.errors: list[str] = []
        self.expected: list[re.Pattern] = []
        self.shots = itertools.count()

    def watch(self, page):
        """Record `page`'s uncaught exceptions (`pageerror`), console errors and crash; returns it."""
        self.pages.append(page)
        page.on("pageerror", lambda error: self.errors.append(f"uncaught {error.name}: {error.message}\n{error.stack}"))
        page.on("console", lambda message: self._console(message))
        page.on("crash", lambda _page: self.errors.append("the page crashed"))
        return page

    def _console(self, message) -> None:
        if message.type == "error":
            self.errors.append(f"console error: {message.text} (at {message.location.get('url')})")

    def expect(self, pattern: str) -> None:
        """Errors matching `pattern` (a regular expression) are provoked on purpose: they do not fail the test."""
        self.expected.append(re.compile(pattern))

    def unexpected(self) -> list[str]:
        return [error for error in self.errors if not any(pattern.search(error) for pattern in self.expected)]

    def check(self) -> None:
        """Fail (with a screenshot of each page) when a page reported an error nobody expected."""
        for page in self.pages:
            if not page.is_closed():
                page.evaluate("0")  # a round trip: events the page sent before are delivered
        unexpected = self.unexpected()
        if unexpected:
            for page in self.pages:
                if not page.is_closed():
                    screenshot(page, f"page_error_{next(self.shots)}")
            raise AssertionError(
                "the page reported errors (screenshots: test-artifacts/dashboard/page_error_*.png):\n"
                + "\n".join(unexpected)
            )


class WatchedBrowser:
    """A Playwright browser whose every page is watched by `errors`. Each page has a browser context of its
    own (cookies, storage and cache), closed with it."""

    def __init__(self, instance, errors: PageErrors):
        self.instance = instance
        self.errors = errors

    def new_page(self, **options):
        return self.errors.watch(self.instance.new_page(**options))


@contextmanager
def headless_chromium():
    """Debian's headless Chromium under Playwright (never a downloaded browser), for `browser(instance)`."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        instance = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            yield instance
        finally:
            instance.close()


@contextmanager
def browser(instance=None):
    """A WatchedBrowser on Chromium `instance` (one started for this block when None): a page error nobody
    expected fails the test when the block ends, and the pages opened in the block are closed then."""
    with ExitStack() as stack:
        if instance is None:
            instance = stack.enter_context(headless_chromium())
        watched = WatchedBrowser(instance, PageErrors())
        stack.callback(lambda: [page.close() for page in watched.errors.pages if not page.is_closed()])
        yield watched
        watched.errors.check()


def screenshot(page, name: str) -> Path:
    """Write a full-page screenshot as a test artifact under test-artifacts/dashboard/."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    path = ARTIFACTS / f"{name}.png"
    page.screenshot(path=str(path), full_page=True)
    return path
