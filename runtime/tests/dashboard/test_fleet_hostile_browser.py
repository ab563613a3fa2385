"""The fleet page in headless Chromium while a Zenoh peer publishes junk: no page error, no link other than
http(s), the token out of reach, and a silent robot shown offline before it goes away."""

import json

import pytest
from dashboard_support import browser, screenshot
from fleet_support import running_fleet, status, wait_linked, zenoh_peer

pytestmark = [pytest.mark.browser, pytest.mark.process]

PAGE_TIMEOUT_MS = 30_000
TOKEN = "fleet-token-SECRET"
STEAL = "javascript:document.title='stolen:'+sessionStorage.getItem('joshua-dashboard-token')"
JUNK = {
    "a_list": "[1,2,3]",
    "nodes_string": '{"nodes": "abc"}',
    "evil": json.dumps({"nodes": [{"name": "n", "state": "running"}], "url": STEAL}),
    "evil_data": json.dumps({"nodes": [], "url": "data:text/html,<script>alert(1)</script>"}),
}


def open_page(chromium, url: str):
    """A page of the fleet whose errors (uncaught exceptions, console errors) the test collects."""
    page = chromium.new_page(viewport={"width": 1200, "height": 700})
    page.set_default_timeout(PAGE_TIMEOUT_MS)
    errors = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.on("console", lambda message: errors.append(message.text) if message.type == "error" else None)
    page.goto(url)
    return page, errors


def test_junk_from_a_peer_neither_breaks_the_page_nor_reaches_the_token(tmp_path):
    with running_fleet(tmp_path, "--offline-after", "2", "--forget-after", "8", token=TOKEN) as fleet:
        with zenoh_peer(fleet.endpoint) as peer, browser() as chromium:
            wait_linked(peer)
            for name, payload in JUNK.items():
                peer.put(f"joshua/{name}/status", payload)
            peer.put("joshua/good/status", status("good"))
            page, errors = open_page(chromium, f"{fleet.url}/#token={TOKEN}")
            card = page.get_by_test_id("robot-good")
            card.get_by_text("1 / 1 processes running").wait_for()
            assert card.get_by_role("link").get_attribute("href") == "http://good.example:8640/"
            assert page.locator("a[href^='javascript:'], a[href^='data:']").count() == 0
            for name in JUNK:
                assert page.get_by_test_id(f"robot-{name}").count() == 0
            screenshot(page, "fleet_hostile_peers")
            card.get_by_text("offline").wait_for()
            card.wait_for(state="detached")
            page.get_by_text("No robot has published yet.").wait_for()
            assert "stolen" not in page.title()
            assert errors == []


def test_the_page_shows_only_http_links_and_valid_entries_whatever_the_server_answers(tmp_path):
    hostile = [
        {"name": "evil", "nodes": [], "last_seen_s": 0.1, "online": True, "url": STEAL},
        {"name": "broken", "nodes": "abc", "last_seen_s": 0.1, "online": True, "url": None},
        {
            "name": "good",
            "nodes": [{"name": "leader", "state": "running"}],
            "last_seen_s": 0.1,
            "online": True,
            "url": "https://good.example/",
        },
        [1, 2, 3],
    ]
    with running_fleet(tmp_path) as fleet, browser() as chromium:
        page = chromium.new_page()
        page.set_default_timeout(PAGE_TIMEOUT_MS)
        errors = []
        page.on("pageerror", lambda error: errors.append(str(error)))
        page.route("**/api/robots", lambda route: route.fulfill(json=hostile))
        page.goto(f"{fleet.url}/#token={TOKEN}")
        page.get_by_test_id("robot-good").get_by_role("link").wait_for()
        assert page.get_by_test_id("robot-good").get_by_role("link").get_attribute("href") == "https://good.example/"
        assert page.get_by_test_id("robot-evil").get_by_role("link").count() == 0
        assert page.get_by_test_id("robot-broken").count() == 0
        assert page.locator("a[href^='javascript:']").count() == 0
        page.route("**/api/robots", lambda route: route.fulfill(json={"robots": "not a list"}))
        page.get_by_role("alert").wait_for()
        assert errors == []
