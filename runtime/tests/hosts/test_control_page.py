"""The dashboard page of a robot on two hosts, in Debian's headless Chromium: the processes of both hosts, each with
its host, a node of the other host restarted from the page, and a silent host's processes shown unknown."""

import pytest

from testsupport.split_robot import running_split_robot

CHROMIUM = "/usr/bin/chromium-headless-shell"
CHROMIUM_FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run"]
PAGE_TIMEOUT_MS = 30_000


@pytest.fixture
def robot(tmp_path, request):
    with running_split_robot(tmp_path, request.node.nodeid) as robot:
        yield robot


@pytest.fixture
def page():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            page = chromium.new_page(viewport={"width": 1400, "height": 1000})
            page.set_default_timeout(PAGE_TIMEOUT_MS)
            errors = []
            page.on("pageerror", lambda error: errors.append(str(error)))
            page.on("console", lambda message: errors.append(message.text) if message.type == "error" else None)
            yield page
            assert errors == []
        finally:
            chromium.close()


def test_the_page_shows_the_processes_of_both_hosts_each_with_its_host(robot, page):
    page.goto(f"{robot.dashboard_url}/#token={robot.token()}")
    hosts = {"discovery_server": "arm", "leader": "arm", "host_agent_arm": "arm", "follower": "gpu", "dashboard": "gpu"}
    for name, host in hosts.items():
        cell = page.get_by_test_id(f"node-host-{name}")
        cell.wait_for()
        assert cell.inner_text() == host
    page.get_by_test_id("host-arm").wait_for()
    page.get_by_test_id("node-row-leader").get_by_text("running").wait_for()
    before = robot.node("arm", "leader")["pid"]

    page.get_by_test_id("node-restart-leader").click()
    robot.wait_until(lambda: robot.node("arm", "leader")["pid"] not in (None, before), "the leader restarted")
    after = str(robot.node("arm", "leader")["pid"])
    page.wait_for_function(f"document.querySelector('[data-testid=\"node-pid-leader\"]').textContent === '{after}'")

    assert robot.ctl("arm", "stop", "host_agent_arm").returncode == 0
    page.get_by_test_id("host-arm").get_by_text("arm unreachable").wait_for()
    page.get_by_test_id("node-row-leader").get_by_text("unknown").wait_for()
    page.get_by_test_id("node-row-follower").get_by_text("waiting").wait_for()
    assert page.get_by_test_id("node-pid-leader").inner_text() == "—"
