"""Drives the robot page's process controls in a browser and checks the page after each action, against
what the supervisor itself says (its control socket) and what the build says (the manifest)."""

import json
import re
import time
from pathlib import Path

from dashboard_support import control_request, screenshot

from joshua_codegen.supervisor.policy import STOP_EXTENSION_MAX_S
from joshua_runtime.dashboard.robot_view import load_robot_view

PAGE_TIMEOUT_MS = 60_000  # a simulation or LeRobot import starting on a busy machine
# A node's stop, and so its restart, may be held as long as the node asks (the recorder saving while LeRobot
# loads, which took more than 60 s on a busy machine), up to STOP_EXTENSION_MAX_S after its SIGINT.
STOP_TIMEOUT_MS = PAGE_TIMEOUT_MS + int(STOP_EXTENSION_MAX_S * 1000)
POLL_S = 0.05
LOG_REFRESHES = 3  # the log dialog must survive several refreshes (a crash showed at the second)
# What a browser logs while the dashboard it talks to restarts: its connections fail or are cut.
CONNECTION_LOST = (
    r"net::ERR_(CONNECTION_REFUSED|CONNECTION_RESET|EMPTY_RESPONSE|CONNECTION_CLOSED|INCOMPLETE_CHUNKED_ENCODING)"
)
STALE_TEXT = re.compile(r"^stale · [0-9.]+ (s|min|h)")
SHOWN_DATA = {"joints": "joint-values-{}", "image": "camera-{}", "scan": "scan-{}"}  # a stream's drawing


class RobotPage:
    """One robot's page in `page`, its supervisor at `control_socket`, its build's `manifest`; `label`
    names its screenshots."""

    def __init__(self, page, errors, control_socket: Path, manifest: Path, label: str):
        self.page, self.errors, self.control_socket, self.name = page, errors, control_socket, label
        data = json.loads(manifest.read_text())
        self.robot = data["robot"]["name"]
        self.critical = {p["name"]: p["critical"] for p in data["processes"]}
        self.dashboard = next((p["name"] for p in data["processes"] if p["type"] == "DASHBOARD"), None)
        process_of = {n["name"]: n["simulated_by"] or n["name"] for n in data["nodes"]}
        publishers = {t["name"]: {process_of[p["node"]] for p in t["publishers"]} for t in data["topics"]}
        view = load_robot_view(manifest)
        # The streams the page draws that only this process publishes: they go stale when it stops.
        self.streams_of = {
            process: [(s.topic, s.kind) for s in view.streams if s.kind != "rate" and publishers[s.topic] == {process}]
            for process in self.critical
        }
        self.shots = 0

    # What the supervisor says

    def node(self, name: str) -> dict:
        return next(
            n for n in control_request(self.control_socket, {"command": "status"})["nodes"] if n["name"] == name
        )

    def wait(self, condition, what: str, timeout_ms: int = PAGE_TIMEOUT_MS) -> None:
        deadline = time.monotonic() + timeout_ms / 1000
        while time.monotonic() < deadline:
            if self.errors.unexpected():
                try:
                    self.errors.check()  # the page broke meanwhile: say how, without waiting any longer
                except AssertionError as exc:
                    raise AssertionError(f"{exc}\n{self.robot_state()}") from None
            if condition():
                return
            self.page.wait_for_timeout(POLL_S * 1000)  # lets the page's events reach the listeners meanwhile
        self.shot(f"timeout_{what}")
        raise AssertionError(f"{self.name}: {what} did not happen within {timeout_ms / 1000:g} s\n{self.robot_state()}")

    def robot_state(self) -> str:
        """What the supervisor says of each process (a robot stopped by a critical failure explains a lost page)."""
        try:
            nodes = control_request(self.control_socket, {"command": "status"})["nodes"]
        except OSError as exc:
            return f"the supervisor does not answer ({exc}): the robot stopped"
        return "supervisor: " + ", ".join(f"{n['name']} {n['state']} ({n['restarts']} restarts)" for n in nodes)

    # What the page shows

    def shot(self, step: str) -> None:
        self.shots += 1
        screenshot(self.page, f"controls_{self.name}_{self.shots:02d}_{step}")

    def check(self, step: str) -> None:
        """The page is still there (not blanked by an error) and reported no error; keep a screenshot."""
        assert self.page.get_by_test_id("robot-name").inner_text() == self.robot
        self.errors.check()
        self.shot(step)

    def row(self, process: str):
        return self.page.get_by_test_id(f"node-row-{process}")

    def button(self, action: str, process: str):
        return self.page.get_by_test_id(f"node-{action}-{process}")

    def text(self, locator) -> str | None:
        """The text of `locator` now, or None when the page does not show it (never waits)."""
        return locator.inner_text() if locator.count() == 1 else None

    def shows(self, process: str, state: str, pid) -> bool:
        shown_pid = self.text(self.page.get_by_test_id(f"node-pid-{process}"))
        shown_state = self.text(self.row(process).get_by_test_id("state"))
        return shown_state == state and shown_pid == (str(pid) if pid else "—")

    def live(self) -> bool:
        return (self.text(self.page.get_by_test_id("connection")) or "").strip() == "live"

    def show(self, topic: str, kind: str) -> None:
        if kind == "joints":
            self.page.get_by_test_id(f"joint-tab-{topic}").click()

    def stale_marker(self, topic: str, kind: str):
        self.show(topic, kind)
        return self.page.get_by_test_id(f"stale-{topic}")

    def wait_until_ready(self, process: str) -> None:
        """The process told the supervisor it is ready, and the page shows it (as someone would wait for
        before the next action: a node stopped while it connects to its device is another test's matter)."""
        ready = self.page.get_by_test_id(f"node-ready-{process}")
        self.wait(lambda: self.node(process)["ready"] and ready.count() == 1, f"{process}_ready")

    def wait_for_live_data(self, process: str) -> None:
        for topic, kind in self.streams_of[process]:
            self.show(topic, kind)
            self.page.get_by_test_id(SHOWN_DATA[kind].format(topic)).wait_for()
            marker = self.page.get_by_test_id(f"stale-{topic}")
            self.wait(lambda marker=marker: marker.count() == 0, f"live_{topic}")

    # The controls

    def click(self, action: str, process: str, confirm: bool) -> None:
        """Press a button; when `confirm`, the page must ask first (and is answered yes), else it must not."""
        button = self.button(action, process)
        assert button.is_enabled(), f"{action} {process} is disabled"
        button.click()
        dialog = self.page.get_by_test_id("confirm-dialog")
        if confirm:
            dialog.wait_for()
            assert process in dialog.inner_text()
            self.shot(f"confirm_{action}_{process}")
            self.page.get_by_test_id("confirm-action").click()
        else:
            assert dialog.count() == 0, f"{action} {process} asked for a confirmation"

    def open_log(self, process: str) -> None:
        self.button("logs", process).click()
        lines = self.page.get_by_test_id("log-lines")
        self.wait(
            lambda: lines.count() == 1 and int(lines.get_attribute("data-loads") or 0) >= LOG_REFRESHES,
            f"log_of_{process}",
        )
        assert process in self.page.get_by_role("dialog").inner_text()
        self.check(f"log_{process}")
        self.page.get_by_test_id("log-close").click()
        self.page.get_by_role("dialog").wait_for(state="detached")

    def restart(self, process: str) -> None:
        old = self.node(process)["pid"]
        self.click("restart", process, confirm=process == self.dashboard)
        self.wait(
            lambda: self.node(process)["pid"] not in (None, old) and self.node(process)["state"] == "running",
            f"restart_of_{process}",
            STOP_TIMEOUT_MS,
        )
        pid = self.node(process)["pid"]
        self.wait(lambda: self.live() and self.shows(process, "running", pid), f"page_after_restart_of_{process}")
        self.wait_until_ready(process)
        self.check(f"restarted_{process}")

    def stop(self, process: str) -> None:
        self.wait_for_live_data(process)
        self.click("stop", process, confirm=self.critical[process] or process == self.dashboard)
        if process != self.dashboard:
            self.open_log(process)  # while it stops and its streams go stale (its refreshes take seconds)
        self.wait(lambda: self.node(process)["state"] == "stopped", f"stop_of_{process}", STOP_TIMEOUT_MS)
        if process == self.dashboard:
            self.wait(lambda: not self.live(), "page_notices_its_dashboard_stopped")
            self.page.get_by_test_id("status-age").filter(has_text="not live: as of").wait_for()
            assert self.button("restart", process).is_disabled()  # nothing answers the page now
            self.check("dashboard_stopped")
            control_request(self.control_socket, {"command": "start", "node": process})  # the page cannot
            return
        self.wait(lambda: self.shows(process, "stopped", None), f"page_after_stop_of_{process}")
        assert self.button("start", process).is_enabled() and self.button("stop", process).is_disabled()
        for topic, kind in self.streams_of[process]:
            marker = self.stale_marker(topic, kind)
            self.wait(lambda marker=marker: marker.count() == 1, f"stale_{topic}")
            assert STALE_TEXT.match(marker.inner_text()), marker.inner_text()
        self.check(f"stopped_{process}")

    def start(self, process: str) -> None:
        if process != self.dashboard:
            self.click("start", process, confirm=False)
        self.wait(lambda: self.node(process)["state"] == "running", f"start_of_{process}")
        pid = self.node(process)["pid"]
        self.wait(lambda: self.live() and self.shows(process, "running", pid), f"page_after_start_of_{process}")
        assert self.button("start", process).is_disabled()
        self.wait_until_ready(process)
        self.wait_for_live_data(process)
        self.check(f"started_{process}")

    def exercise(self, process: str) -> None:
        """Its log, a restart, a stop and a start, the page checked after each. A node's log is read while
        it stops; the dashboard's before its restart (its stop takes the log away with the page's server)."""
        if process == self.dashboard:
            self.errors.expect(CONNECTION_LOST)
            self.open_log(process)
        self.restart(process)
        self.stop(process)
        self.start(process)
