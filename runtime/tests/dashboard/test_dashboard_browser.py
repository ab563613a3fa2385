"""The dashboard page in Debian's headless Chromium, against a robot run by its generated supervisor.py.

The robot: a mock leader arm (restarted from the page), a recorder (episodes started and stopped from
the page, saved by LeRobot), a probe arm stopped from the page so that this test publishes its topic
with values it knows, and the dashboard process the description's `dashboard { }` block adds.
"""

import re

import pandas
import pytest
from dashboard_support import (
    EventReader,
    browser,
    control_request,
    dashboard_token,
    free_port,
    get_json,
    node_pid,
    running_robot,
    screenshot,
)
from sensor_msgs.msg import JointState

pytestmark = [pytest.mark.browser, pytest.mark.process]

PAGE_TIMEOUT_MS = 30_000
RECORDER_START_TIMEOUT_MS = 120_000  # LeRobot's import in a cold process on a busy machine
PROBE_JOINTS = ["shoulder_pan", "gripper"]
PROBE = {"position": [0.125, -1.5], "velocity": [2.25, 0.0], "effort": [-0.375, 3.0]}
TASK = "pick the red cube"
RECORDING_S = 1.5  # long enough for frames at the recorder's 10 fps on a busy machine


def description(output_directory, port: int) -> str:
    return f"""robot_config {{
  name: "dash_robot"
  mode: MODE_DATA_COLLECTION
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 30 }}
  node {{ name: "probe" type: MOCK_ENCODER_PUBLISHER topic_name: "/probe/joint_states" rate_hz: 10
          joint_names: ["shoulder_pan", "gripper"] device_ids: [1, 2] }}
  node {{ name: "recorder" type: DATA_SUBSCRIBER topic_name: "/leader/joint_states" rate_hz: 10
          input_topics: ["/leader/joint_states"]
          output_directory: "{output_directory}" output_format: "parquet" }}
  dashboard {{ port: {port} }}
}}
"""


@pytest.fixture
def robot(tmp_path, ros_env):
    port = free_port()
    env = dict(ros_env, HF_HUB_OFFLINE="1", HF_DATASETS_OFFLINE="1")
    with running_robot(description(tmp_path / "dataset", port), tmp_path, env, port) as control_socket:
        yield f"http://127.0.0.1:{port}", control_socket, tmp_path / "dataset"


@pytest.fixture
def chromium():
    """The browser: a page error nobody expected fails the test (see dashboard_support.PageErrors)."""
    with browser() as instance:
        yield instance


@pytest.fixture
def page(chromium):
    page = chromium.new_page(viewport={"width": 1400, "height": 1000})
    page.set_default_timeout(PAGE_TIMEOUT_MS)
    return page


def probe_message() -> JointState:
    return JointState(name=PROBE_JOINTS, **PROBE)


def test_page_shows_published_values_restarts_a_node_and_records_an_episode(robot, page, ros_client):
    url, control_socket, dataset = robot
    token = dashboard_token(control_socket)
    probe = ros_client.node.create_publisher(JointState, "/probe/joint_states", 10)
    events = EventReader(url, token, keep=False)
    page.goto(f"{url}/#token={token}")
    page.get_by_test_id("node-stop-probe").click()
    page.get_by_test_id("confirm-action").click()  # probe is critical (the default): the page asks first
    page.get_by_test_id("node-row-probe").get_by_text("stopped").wait_for()
    assert node_pid(control_socket, "probe") is None
    nodes = {node["name"]: node for node in control_request(control_socket, {"command": "status"})["nodes"]}
    assert nodes["dashboard"]["ready"]  # it told the supervisor (sd_notify) once it served
    ros_client.node.create_timer(0.05, lambda: probe.publish(probe_message()))
    page.get_by_role("tab", name="/probe/joint_states").click()

    for quantity, values in PROBE.items():
        for joint, value in zip(PROBE_JOINTS, values):
            cell = page.get_by_test_id(f"joint-/probe/joint_states-{joint}-{quantity}")
            expected = f"{value:g}"
            ros_client.spin_until(
                lambda cell=cell, expected=expected: cell.count() == 1 and cell.inner_text() == expected,
                PAGE_TIMEOUT_MS / 1000,
            )
            assert cell.inner_text() == expected, f"{joint} {quantity}"

    old_pid = node_pid(control_socket, "leader")
    assert page.get_by_test_id("node-pid-leader").inner_text() == str(old_pid)
    page.get_by_test_id("node-restart-leader").click()
    _wait(page, ros_client, lambda: node_pid(control_socket, "leader") not in (None, old_pid))
    new_pid = node_pid(control_socket, "leader")
    page.get_by_test_id("node-pid-leader").filter(has_text=str(new_pid)).wait_for()
    assert {node["name"]: node["pid"] for node in get_json(url + "/api/status", token)["nodes"]}["leader"] == new_pid
    screenshot(page, "robot_page")

    # The recorder starts an episode by itself; stop it, then record one started from the page.
    state = page.get_by_test_id("recording-state-recorder")
    message = page.get_by_test_id("recorder-message-recorder")
    _wait(page, ros_client, lambda: state.inner_text() == "recording", RECORDER_START_TIMEOUT_MS)
    ros_client.spin_until(lambda: False, RECORDING_S)
    page.get_by_test_id("episode-stop-recorder").click()
    _wait(page, ros_client, lambda: state.inner_text() == "idle" and "saved episode 0" in message.inner_text())
    page.get_by_test_id("episode-task-recorder").fill(TASK)
    page.get_by_test_id("episode-start-recorder").click()
    _wait(page, ros_client, lambda: state.inner_text() == "recording")
    ros_client.spin_until(lambda: False, RECORDING_S)
    progress = page.get_by_test_id("episode-progress-recorder")  # the recorder's own timer and frame count
    _wait(page, ros_client, lambda: re.fullmatch(r"episode 1 · 0:0\d · [1-9]\d* frames", progress.inner_text()))
    screenshot(page, "robot_page_recording")
    page.get_by_test_id("episode-stop-recorder").click()
    saved = page.get_by_test_id("episodes-saved-recorder")
    _wait(page, ros_client, lambda: saved.inner_text() == "2 episodes saved", RECORDER_START_TIMEOUT_MS)
    assert "saved episode 1" in message.inner_text()

    page.get_by_test_id("node-logs-recorder").click()
    page.get_by_test_id("log-lines").filter(has_text="episode 1 saved").wait_for()
    screenshot(page, "robot_page_log_tail")

    tasks = pandas.read_parquet(dataset / "meta" / "tasks.parquet")
    assert TASK in set(tasks.index) | set(tasks.get("task", []))
    assert {"joints", "recorder", "status", "actions", "rates", "clock"} <= events.kinds()
    events.check()


def test_the_address_with_the_token_opens_the_page_which_drops_it_and_keeps_working(tmp_path, ros_env, chromium, page):
    port = free_port()
    description = f"""robot_config {{ name: "token_robot" mode: MODE_TELEOPERATION
  node {{ name: "leader" type: CUSTOM executable: "/bin/sleep" args: ["600"] }}
  dashboard {{ port: {port} }}
}}
"""
    with running_robot(description, tmp_path, ros_env, port) as control_socket:
        token = dashboard_token(control_socket)
        url = f"http://127.0.0.1:{port}/"
        page.goto(f"{url}#token={token}")
        page.get_by_test_id("robot-name").filter(has_text="token_robot").wait_for()
        assert page.url == url  # the token left the address bar (and the history)
        page.reload()
        page.get_by_test_id("node-row-leader").get_by_text("running").wait_for()
        assert page.url == url
        page.get_by_test_id("node-stop-leader").click()
        page.get_by_test_id("confirm-action").click()  # leader is critical (the default): the page asks first
        page.get_by_test_id("node-row-leader").get_by_text("stopped").wait_for()
        assert node_pid(control_socket, "leader") is None

        # Another browser without the token (a bookmark, the fleet view's link) is asked for it.
        other = chromium.new_page()
        other.goto(url)
        other.get_by_test_id("token-input").wait_for()
        chromium.errors.check()  # a tab without a token asks for it and sends nothing to be refused
        chromium.errors.expect(r"status of 401 \(Unauthorized\)")  # the wrong token, refused on purpose
        other.get_by_test_id("token-input").fill("not-the-token-of-this-robot")
        other.get_by_test_id("token-submit").click()
        other.get_by_text("The token this tab had was refused.").wait_for()
        screenshot(other, "token_prompt")
        other.get_by_test_id("token-input").fill(token)
        other.get_by_test_id("token-submit").click()
        other.get_by_test_id("node-start-leader").click()
        other.get_by_test_id("node-row-leader").get_by_text("running").wait_for()
        assert node_pid(control_socket, "leader") is not None
        screenshot(other, "robot_page_after_token_prompt")
        chromium.errors.check()
        for tab in (page, other):
            tab.close()  # before the robot stops: its pages would log their lost connection


def _wait(page, ros_client, condition, timeout_ms: int = PAGE_TIMEOUT_MS) -> None:
    """Spin the test's ROS client (it publishes the probe) until `condition()` holds."""
    if not ros_client.spin_until(condition, timeout_ms / 1000, every=None):
        screenshot(page, "robot_page_timeout")
        pytest.fail(
            f"the page did not reach the expected state within {timeout_ms / 1000:g} s "
            "(test-artifacts/dashboard/robot_page_timeout.png shows it)"
        )
