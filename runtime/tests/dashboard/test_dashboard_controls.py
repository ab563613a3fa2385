"""Every process control of the robot page in headless Chromium, on each robot of config/robots/ that runs
without hardware: for every process its log, a restart, a stop and a start, the page checked after each
(no page error, the supervisor's state and pid shown, the streams of a stopped process marked stale).
Also a restart's pending state in every open page, the confirmation a critical stop asks for, and the
page at phone width. Screenshots of each step: test-artifacts/dashboard/controls_*.png."""

import pytest
from config_robots import ROBOTS, devices
from dashboard_support import (
    EventReader,
    browser,
    dashboard_token,
    free_port,
    headless_chromium,
    running_robot,
    screenshot,
)
from page_driver import PAGE_TIMEOUT_MS, RobotPage

from joshua_runtime.dashboard.robot_view import RATE, load_robot_view

pytestmark = [pytest.mark.browser, pytest.mark.process]

ROBOT_TIMEOUT_S = 900  # every process of a simulated robot restarted, stopped and started on a busy machine
PHONE = {"width": 390, "height": 844}
DESKTOP = {"width": 1400, "height": 1000}
# The elements that reach past the right edge of the window, innermost first (what makes a page scroll sideways).
OVERFLOWING = """() => [...document.querySelectorAll("body *")]
  .filter((e) => e.getBoundingClientRect().right > window.innerWidth + 0.5 && !e.closest("[data-scrolls]"))
  .filter((e) => ![...e.children].some((c) => c.getBoundingClientRect().right > window.innerWidth + 0.5))
  .map((e) => `${e.tagName.toLowerCase()}.${e.className.baseVal ?? e.className} right=${e.getBoundingClientRect().right}`)
  .slice(0, 40)"""


@pytest.fixture(scope="module")
def module_chromium():
    """One Chromium for the tests of this module (a start costs seconds); each page has a browser context of
    its own, and each test its own watch for page errors."""
    with headless_chromium() as instance:
        yield instance


def open_page(chromium, port: int, control_socket, viewport=DESKTOP):
    page = chromium.new_page(viewport=viewport)
    page.set_default_timeout(PAGE_TIMEOUT_MS)
    page.goto(f"http://127.0.0.1:{port}/#token={dashboard_token(control_socket)}")
    return page


@pytest.mark.timeout(ROBOT_TIMEOUT_S)
@pytest.mark.parametrize("label", list(ROBOTS))
def test_every_process_control_of_a_robot_of_config(label, tmp_path, ros_env, module_chromium):
    robot = ROBOTS[label]
    port = free_port()
    with devices(robot, tmp_path) as overrides:
        overrides += [f"dashboard.port={port}", "dashboard.bind=127.0.0.1"]
        with (
            running_robot(robot.description, tmp_path, ros_env, port, overrides) as control_socket,
            browser(module_chromium) as chromium,
        ):
            page = open_page(chromium, port, control_socket)
            driver = RobotPage(page, chromium.errors, control_socket, tmp_path / "out" / "manifest.json", label)
            processes = [name for name in driver.critical if name != driver.dashboard] + [driver.dashboard]
            for process in processes:
                driver.row(process).wait_for()
            driver.check("opened")
            events = EventReader(f"http://127.0.0.1:{port}", dashboard_token(control_socket), keep=False)
            for kind in sorted(robot_events(tmp_path / "out" / "manifest.json")):
                events.wait_for_kind(kind)
            for process in processes:
                driver.exercise(process)
            events.check()  # every event until the dashboard's own restart ended the stream


def robot_events(manifest) -> set[str]:
    """The events a robot's dashboard sends while all runs: its streams drawn, its recorders and inference nodes."""
    view = load_robot_view(manifest)
    kinds = {"clock", "status", "actions", "rates"} | {s.kind for s in view.streams if s.kind != RATE}
    return kinds | ({"recorder"} if view.recorders else set()) | ({"inference"} if view.inferences else set())


# A node that ignores SIGINT, so that its restart lasts the robot's SIGINT grace; one that is not critical.
PENDING = """robot_config {{ name: "pending_robot" mode: MODE_TELEOPERATION
  shutdown {{ sigint_grace_s: 2 sigterm_grace_s: 1 }}
  node {{ name: "stubborn" type: CUSTOM executable: "/bin/sh" args: ["-c", "trap '' INT; exec sleep 600"] }}
  node {{ name: "helper" type: CUSTOM executable: "/bin/sleep" args: ["600"] critical: false }}
  dashboard {{ port: {port} }}
}}
"""


def test_a_restart_is_pending_in_every_page_and_a_critical_stop_asks_first(tmp_path, ros_env, module_chromium):
    port = free_port()
    with (
        running_robot(PENDING.format(port=port), tmp_path, ros_env, port) as control_socket,
        browser(module_chromium) as chromium,
    ):
        pages = [open_page(chromium, port, control_socket) for _ in range(2)]
        driver = RobotPage(pages[0], chromium.errors, control_socket, tmp_path / "out" / "manifest.json", "pending")
        for page in pages:
            page.get_by_test_id("node-row-stubborn").get_by_text("running").wait_for()
        old = driver.node("stubborn")["pid"]
        driver.click("restart", "stubborn", confirm=False)
        for page in pages:  # the restart takes the 2 s SIGINT grace: both pages show it meanwhile
            page.get_by_test_id("node-pending-stubborn").filter(has_text="restarting").wait_for()
            assert page.get_by_test_id("node-start-stubborn").is_disabled()
            assert page.get_by_test_id("node-stop-stubborn").is_disabled()
            assert page.get_by_test_id("node-stop-helper").is_enabled()
        screenshot(pages[1], "controls_pending_restart")
        driver.wait(lambda: driver.node("stubborn")["pid"] not in (None, old), "restart")
        for page in pages:
            page.get_by_test_id("node-pending-stubborn").wait_for(state="detached")
        new = driver.node("stubborn")
        driver.wait(lambda: driver.shows("stubborn", "running", new["pid"]), "page_after_restart")
        restarts = pages[0].get_by_test_id("node-restarts-stubborn").inner_text()
        assert restarts.split()[0] == str(new["restarts"]), restarts

        # stubborn is critical (the default): its stop asks first, and a "no" leaves it running.
        driver.button("stop", "stubborn").click()
        dialog = pages[0].get_by_test_id("confirm-dialog")
        assert "critical" in dialog.inner_text()
        screenshot(pages[0], "controls_confirm_critical_stop")
        pages[0].get_by_test_id("confirm-cancel").click()
        dialog.wait_for(state="detached")
        assert driver.node("stubborn")["pid"] == new["pid"] and driver.node("stubborn")["state"] == "running"
        driver.click("stop", "helper", confirm=False)  # not critical: no question
        driver.wait(lambda: driver.shows("helper", "stopped", None), "helper_stopped")
        driver.click("start", "helper", confirm=False)
        driver.wait(lambda: driver.node("helper")["state"] == "running", "helper_started")
        driver.check("pending_robot_done")


def test_the_page_at_phone_width_has_every_control_in_reach(tmp_path, ros_env, module_chromium):
    port = free_port()
    overrides = [f"dashboard.port={port}"]
    with running_robot(ROBOTS["mock_arm"].description, tmp_path, ros_env, port, overrides) as control_socket:
        with browser(module_chromium) as chromium:
            page = open_page(chromium, port, control_socket, PHONE)
            driver = RobotPage(page, chromium.errors, control_socket, tmp_path / "out" / "manifest.json", "phone")
            for testid in (
                "node-row-lidar",
                "camera-/camera/image_raw",
                "scan-/scan",
                "joint-values-/follower/joint_states",
            ):
                page.get_by_test_id(testid).wait_for()
            screenshot(page, "phone_page")
            overflowing = page.evaluate(OVERFLOWING)
            assert overflowing == [], "\n".join(overflowing)
            assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
            controls = page.locator("main button, main input, header button")
            assert controls.count() >= 4 * 5  # restart, stop, start, logs of every process, and more
            for index in range(controls.count()):
                control = controls.nth(index)
                control.scroll_into_view_if_needed()
                box = control.bounding_box()
                assert box and box["x"] >= 0 and box["x"] + box["width"] <= PHONE["width"], control.evaluate(
                    "e => e.outerHTML"
                )
            driver.open_log("leader")
            driver.restart("leader")
            assert page.evaluate(OVERFLOWING) == []
            assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
            screenshot(page, "phone_page_after_restart")
