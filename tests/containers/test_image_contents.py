"""What the final stage of an image holds, and what it leaves out: no compiler, no npm, no test dependency, no
build secret; a user that is not root, in the groups devices belong to."""

import hashlib
import re
import tomllib

import pytest
from robot_container import ROOT

from testsupport.podman import BUILD_TIMEOUT_S

pytestmark = pytest.mark.timeout(BUILD_TIMEOUT_S)
BUILD_TOOLS = ("gcc", "g++", "cc", "c++", "make", "ld", "npm", "npx", "node")
CA_SECRET_PATH = "/run/secrets/ca-certificates"
REQUIREMENT_NAME = re.compile(r"[A-Za-z0-9._-]+")


def in_image(podman, image: str, script: str):
    return podman.run("run", "--rm", "--network=none", "--entrypoint", "sh", image, "-c", script, check=False)


def normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def dev_dependencies() -> set[str]:
    """The project's development dependencies, as distribution names (what the image must not hold)."""
    groups = tomllib.loads((ROOT / "pyproject.toml").read_text())["dependency-groups"]
    names = {normalized(REQUIREMENT_NAME.match(requirement).group()) for requirement in groups["dev"]}
    return {name for name in names if not name.startswith("joshua-")}  # the workspace's own packages


@pytest.mark.parametrize("image_fixture", ["mock_arm_image", "servo_arm_image"])
def test_the_final_image_holds_no_compiler_npm_or_test_dependency(podman, image_fixture, request):
    image = request.getfixturevalue(image_fixture)
    found = in_image(podman, image, f"for tool in {' '.join(BUILD_TOOLS)}; do command -v $tool; done; true")
    assert found.stdout == "", found.stdout
    listed = in_image(
        podman, image, "/opt/joshua/venv/bin/python -m pip list --format freeze --disable-pip-version-check"
    )
    assert listed.returncode == 0, listed.stderr
    installed = {normalized(line.split("==")[0]) for line in listed.stdout.split()}
    assert {"joshua-runtime", "joshua-core", "ros-rclpy"} <= installed
    assert installed.isdisjoint(dev_dependencies()), installed & dev_dependencies()


def test_the_image_runs_as_a_user_in_the_dialout_and_video_groups(podman, mock_arm_image):
    identity = in_image(podman, mock_arm_image, "id")
    assert re.match(
        r"uid=1000\(joshua\) gid=1000\(joshua\) groups=1000\(joshua\),20\(dialout\),44\(video\)", identity.stdout
    )


def test_the_build_secret_is_not_kept_in_the_image(podman, mock_arm_image, build_ca_bundle):
    """pip trusted the CA bundle `make image` passed while it installed; the bundle stays out of every layer."""
    data = build_ca_bundle.read_bytes()
    digest, size = hashlib.sha256(data).hexdigest(), len(data)
    found = in_image(
        podman,
        mock_arm_image,
        f"test ! -e {CA_SECRET_PATH} || echo {CA_SECRET_PATH}; "
        f"find / -xdev -type f -size {size}c -exec sha256sum {{}} + 2>/dev/null | grep {digest} || true",
    )
    assert found.stdout == "", found.stdout
    history = podman.run("history", "--no-trunc", "--format", "{{.CreatedBy}}", mock_arm_image).stdout
    assert "BEGIN CERTIFICATE" not in history
