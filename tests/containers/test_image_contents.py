"""What the final stage of an image holds, and what it leaves out: no compiler, no npm, no test dependency, no
build secret; a user that is not root, in the groups devices belong to."""

import hashlib
import json
import re
import tomllib

import pytest
from robot_container import ROOT

from testsupport.podman import BUILD_TIMEOUT_S

pytestmark = pytest.mark.timeout(BUILD_TIMEOUT_S)
BUILD_TOOLS = ("gcc", "g++", "cc", "c++", "make", "ld", "npm", "npx", "node")
CA_SECRET_PATH = "/run/secrets/ca-certificates"
REQUIREMENT_NAME = re.compile(r"[A-Za-z0-9._-]+")
# Run by the image's Python: every installed distribution, and the names any installed distribution requires.
INSTALLED_AND_REQUIRED = """
import importlib.metadata, json, re
name = re.compile(r"[A-Za-z0-9._-]+")
dists = list(importlib.metadata.distributions())
print(json.dumps({
    "installed": [d.metadata["Name"] for d in dists],
    "required": [name.match(r).group() for d in dists for r in d.requires or []],
}))
"""


def in_image(podman, image: str, script: str):
    return podman.run("run", "--rm", "--network=none", "--entrypoint", "sh", image, "-c", script, check=False)


def normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def dev_dependencies() -> set[str]:
    """The project's development dependencies, as distribution names (what the image must not hold)."""
    groups = tomllib.loads((ROOT / "pyproject.toml").read_text())["dependency-groups"]
    names = {normalized(REQUIREMENT_NAME.match(requirement).group()) for requirement in groups["dev"]}
    return {name for name in names if not name.startswith("joshua-")}  # the workspace's own packages


@pytest.mark.parametrize("image_fixture", ["sim_image", "servo_arm_image"])  # without and with a C++ stage
def test_the_final_image_holds_no_compiler_npm_or_test_dependency(podman, image_fixture, request):
    image = request.getfixturevalue(image_fixture)
    found = in_image(podman, image, f"for tool in {' '.join(BUILD_TOOLS)}; do command -v $tool; done; true")
    assert found.stdout == "", found.stdout
    listed = in_image(podman, image, f"/opt/joshua/venv/bin/python -c '{INSTALLED_AND_REQUIRED}'")
    assert listed.returncode == 0, listed.stderr
    found = json.loads(listed.stdout)
    installed, required = ({normalized(name) for name in found[key]} for key in ("installed", "required"))
    assert {"joshua-runtime", "joshua-core", "ros-rclpy"} <= installed
    # A development dependency may be in the image only as what the robot's own packages need (mujoco requires
    # mujoco-studio, which requires websockets, which the tests' Foxglove client uses too).
    development_only = (installed & dev_dependencies()) - required
    assert development_only == set(), development_only


def test_the_image_runs_as_a_user_in_the_dialout_and_video_groups(podman, sim_image):
    identity = in_image(podman, sim_image, "id")
    assert re.match(
        r"uid=1000\(joshua\) gid=1000\(joshua\) groups=1000\(joshua\),20\(dialout\),44\(video\)", identity.stdout
    )


def test_the_build_secret_is_not_kept_in_the_image(podman, sim_image, build_ca_bundle):
    """pip trusted the CA bundle `make image` passed while it installed; the bundle stays out of every layer."""
    data = build_ca_bundle.read_bytes()
    digest, size = hashlib.sha256(data).hexdigest(), len(data)
    found = in_image(
        podman,
        sim_image,
        f"test ! -e {CA_SECRET_PATH} || echo {CA_SECRET_PATH}; "
        f"find / -xdev -type f -size {size}c -exec sha256sum {{}} + 2>/dev/null | grep {digest} || true",
    )
    assert found.stdout == "", found.stdout
    history = podman.run("history", "--no-trunc", "--format", "{{.CreatedBy}}", sim_image).stdout
    assert "BEGIN CERTIFICATE" not in history
