"""compose.yaml, run with podman-compose: the simulated arm's image serving the checkout's code and dashboard page,
and the fleet view (profile `fleet`) listing it."""

import json
import subprocess
import sys
import time

import pytest
from robot_container import ROOT, exit_code, logs, wait_for_log

from testsupport.podman import BUILD_TIMEOUT_S

pytestmark = pytest.mark.timeout(BUILD_TIMEOUT_S)
COMPOSE = [sys.executable, "-m", "podman_compose", "--file", str(ROOT / "compose.yaml")]
COMPOSE_TIMEOUT_S = 120.0
PROJECT_LABEL = "com.docker.compose.project=joshua-dev"
TOKEN_FILE = "/tmp/joshua-1000/so100_sim.dashboard-token"
PAGE = "http://127.0.0.1:8640/"
FLEET = "http://127.0.0.1:8650/api/robots"
FLEET_TIMEOUT_S = 60.0
POLL_S = 0.5
FETCH = """
import json, sys, urllib.request
headers = {"Authorization": "Bearer " + sys.argv[2]} if sys.argv[2] else {}
request = urllib.request.Request(sys.argv[1], headers=headers)
with urllib.request.urlopen(request, timeout=10) as response:
    sys.stdout.write(response.read().decode())
"""


def compose(podman, netns, image, *args) -> subprocess.CompletedProcess:
    """podman-compose with the session's storage, the image under test and the test's network namespace."""
    env = podman.environment()
    env.update(JOSHUA_DEV_IMAGE=image, JOSHUA_DEV_NETWORK=f"ns:{netns.path}")
    done = subprocess.run(
        [*COMPOSE, *args], cwd=ROOT, env=env, capture_output=True, text=True, timeout=COMPOSE_TIMEOUT_S
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return done


def fetch(netns, url: str, token: str) -> str:
    done = netns.run(sys.executable, "-c", FETCH, url, token, capture_output=True, text=True, timeout=COMPOSE_TIMEOUT_S)
    assert done.returncode == 0, done.stderr
    return done.stdout


def service_container(podman, service: str) -> str:
    names = podman.run(
        "ps",
        "--all",
        "--filter",
        f"label={PROJECT_LABEL}",
        "--filter",
        f"label=com.docker.compose.service={service}",
        "--format",
        "{{.Names}}",
    ).stdout.split()
    assert len(names) == 1, names
    return names[0]


def fleet_robots(netns) -> list[str]:
    """The robots the fleet view lists, once it lists one (its API needs no token on loopback)."""
    deadline = time.monotonic() + FLEET_TIMEOUT_S
    while time.monotonic() < deadline:
        done = netns.run(
            sys.executable, "-c", FETCH, FLEET, "", capture_output=True, text=True, timeout=FLEET_TIMEOUT_S
        )
        if done.returncode == 0 and json.loads(done.stdout):
            return [robot["name"] for robot in json.loads(done.stdout)]
        time.sleep(POLL_S)
    raise AssertionError(f"the fleet view listed no robot within {FLEET_TIMEOUT_S} s")


def test_compose_runs_the_simulated_arm_and_the_fleet_view_with_the_checkouts_code_and_page(podman, sim_image, netns):
    compose(podman, netns, sim_image, "--profile", "fleet", "up", "--detach")
    try:
        robot = service_container(podman, "robot")
        wait_for_log(podman, robot, "supervisor: ready: 3 of 3 nodes ready")
        imported = podman.run("exec", robot, "python3", "-c", "import joshua_runtime; print(joshua_runtime.__file__)")
        assert imported.stdout.strip() == "/src/runtime/joshua_runtime/__init__.py"

        token = podman.run("exec", robot, "cat", TOKEN_FILE).stdout.strip()
        assert fetch(netns, PAGE, token) == (ROOT / "web" / "dist" / "index.html").read_text()
        status = json.loads(fetch(netns, PAGE + "api/status", token))
        assert {node["name"]: node["state"] for node in status["nodes"]} == {
            "leader": "running",
            "simulation": "running",
            "dashboard": "running",
        }
        assert fleet_robots(netns) == ["so100_sim"]

        compose(podman, netns, sim_image, "--profile", "fleet", "stop")
        output = logs(podman, robot)
        assert exit_code(podman, robot) == 0, output
        assert "dashboard: final state: stopped (exited with code 0)" in output
        fleet = service_container(podman, "fleet")
        assert exit_code(podman, fleet) == 0, logs(podman, fleet)
    finally:
        compose(podman, netns, sim_image, "--profile", "fleet", "down")
