"""The fleet view: two robots in different ROS domains publish over zenoh, the fleet page lists both; a robot
whose dashboard stops is shown offline at once, not after --offline-after; an offline robot's card offers no
link to a page that is not there."""

import subprocess
import sys
import time
from contextlib import ExitStack

import pytest
from dashboard_support import (
    browser,
    control_request,
    dashboard_token,
    free_port,
    get_json,
    running_robot,
    screenshot,
    stop,
    wait_for_server,
)
from fleet_support import running_fleet, status, wait_linked, zenoh_peer
from playwright.sync_api import TimeoutError as PlaywrightTimeoutError

pytestmark = [pytest.mark.browser, pytest.mark.process]

PAGE_TIMEOUT_MS = 30_000
STATUS_PERIOD_MS = 500  # a live robot's status comes more often than --offline-after
ROBOTS = ("fleet_alpha", "fleet_beta")
# Silence alone makes no robot offline within a test: what the page shows offline was withdrawn.
NEVER_SILENT_LONG_ENOUGH = ("--offline-after", "600", "--forget-after", "1200")


def description(robot: str, port: int, endpoint: str) -> str:
    return f"""robot_config {{
  name: "{robot}"
  mode: MODE_TELEOPERATION
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 10 }}
  dashboard {{ port: {port} zenoh_connect: "{endpoint}" }}
}}
"""


def test_fleet_page_lists_every_publishing_robot_and_links_to_its_page(tmp_path, ros_env):
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    fleet_port = free_port()
    output = tmp_path / "fleet.log"
    with open(output, "w") as log:
        fleet = subprocess.Popen(
            [sys.executable, "-m", "joshua_runtime.dashboard.fleet", "--listen", endpoint, "--port", str(fleet_port)],
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    fleet_url = f"http://127.0.0.1:{fleet_port}"
    with ExitStack() as robots:
        robots.callback(stop, fleet)
        wait_for_server(f"{fleet_url}/api/robots", fleet, output)
        urls, tokens = {}, {}
        for offset, robot in enumerate(ROBOTS):
            workdir = tmp_path / robot
            workdir.mkdir()
            env = dict(ros_env, ROS_DOMAIN_ID=str(int(ros_env["ROS_DOMAIN_ID"]) + offset))
            port = free_port()
            control_socket = robots.enter_context(running_robot(description(robot, port, endpoint), workdir, env, port))
            urls[robot] = f"http://127.0.0.1:{port}/"
            tokens[robot] = dashboard_token(control_socket)

        with browser() as chromium:
            page = chromium.new_page(viewport={"width": 1200, "height": 700})
            page.set_default_timeout(PAGE_TIMEOUT_MS)
            page.goto(fleet_url + "/")
            for robot in ROBOTS:
                card = page.get_by_test_id(f"robot-{robot}")
                card.get_by_text("2 / 2 processes running").wait_for()
                assert card.get_by_role("link").get_attribute("href") == urls[robot]
            screenshot(page, "fleet_page")
            page.get_by_test_id(f"robot-{ROBOTS[1]}").get_by_role("link").click()
            page.get_by_test_id("token-input").fill(tokens[ROBOTS[1]])  # the link does not carry the robot's token
            page.get_by_test_id("token-submit").click()
            page.get_by_test_id("robot-name").filter(has_text=ROBOTS[1]).wait_for()

        listed = {entry["name"]: entry for entry in get_json(f"{fleet_url}/api/robots")}
        assert set(listed) == set(ROBOTS)
        for robot in ROBOTS:
            assert [node["name"] for node in listed[robot]["nodes"]] == ["leader", "dashboard"]
            assert listed[robot]["last_seen_s"] < 5


def test_a_robot_whose_dashboard_stops_is_offline_on_the_fleet_page_at_once(tmp_path, ros_env):
    port = free_port()
    with (
        running_fleet(tmp_path, *NEVER_SILENT_LONG_ENOUGH) as fleet,
        running_robot(description(ROBOTS[0], port, fleet.endpoint), tmp_path, ros_env, port) as control_socket,
        browser() as chromium,
    ):
        page = chromium.new_page(viewport={"width": 1200, "height": 700})
        page.set_default_timeout(PAGE_TIMEOUT_MS)
        page.goto(fleet.url + "/")
        card = page.get_by_test_id(f"robot-{ROBOTS[0]}")
        card.get_by_text("online", exact=True).wait_for()

        assert control_request(control_socket, {"command": "stop", "node": "dashboard"})["ok"]
        card.get_by_text("offline, last seen").wait_for()
        [entry] = fleet.robots()
        assert entry["online"] is False and entry["last_seen_s"] < 600
        screenshot(page, "fleet_dashboard_stopped")

        # Started again, it publishes its status again and is online.
        assert control_request(control_socket, {"command": "start", "node": "dashboard"})["ok"]
        card.get_by_text("online", exact=True).wait_for()


def publish_until_linked(peer, card) -> None:
    """Publish the robot's status, as a live robot does, until its card links to its page: one status keeps it
    online for --offline-after (1 s) only, which a page loading on a busy machine can miss."""
    deadline = time.monotonic() + PAGE_TIMEOUT_MS / 1000
    while True:
        peer.put("joshua/arm_1/status", status("arm_1"))
        try:
            card.get_by_role("link").wait_for(timeout=STATUS_PERIOD_MS)
            return
        except PlaywrightTimeoutError:
            if time.monotonic() > deadline:
                raise


def test_an_offline_robot_offers_no_link_to_its_page_until_it_is_back(tmp_path):
    with (
        running_fleet(tmp_path, "--offline-after", "1", "--forget-after", "600") as fleet,
        zenoh_peer(fleet.endpoint) as peer,
        browser() as chromium,
    ):
        wait_linked(peer)
        page = chromium.new_page(viewport={"width": 1200, "height": 700})
        page.set_default_timeout(PAGE_TIMEOUT_MS)
        page.goto(fleet.url + "/")
        card = page.get_by_test_id("robot-arm_1")
        publish_until_linked(peer, card)
        assert card.get_by_role("link").get_attribute("href") == "http://arm_1.example:8640/"

        card.get_by_text("offline, last seen").wait_for()  # silent for --offline-after
        assert card.get_by_role("link").count() == 0
        assert card.get_by_test_id("dashboard-offline-arm_1").inner_text() == "Dashboard not reachable"
        screenshot(page, "fleet_offline_robot")

        publish_until_linked(peer, card)
