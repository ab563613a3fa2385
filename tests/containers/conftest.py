"""Container images of robots built with `make image` from a debootstrap base, once per test session.

Podman keeps everything in a directory of the session (testsupport/podman.py) except the builds' cache
mounts: those (the wheels pip downloads) and the base come from the machine's cache
(testsupport/container_base.py). Containers run in a network namespace each test makes, or with no
network at all.
"""

import os
import re
import ssl
import subprocess
import uuid
from pathlib import Path

import pytest

from testsupport import container_base
from testsupport.podman import BUILD_TIMEOUT_S, NetworkNamespace, Podman, engine_missing, unique_name

ROOT = Path(__file__).resolve().parents[2]
BUILT = re.compile(r"make image: built (\S+) ")
# The mock arm with its follower as a real STS3215 servo actuator on /dev/ttyUSB0, running its C++ binary.
SERVO_FOLLOWER = (
    "follower.type=ACTUATOR_SUBSCRIBER",
    "follower.serial_port=/dev/ttyUSB0",
    "follower.preferred_backend=CPP",
)

FLEET_LINK = "dashboard.zenoh_connect=tcp/127.0.0.1:7447"  # where compose.yaml's fleet view listens


@pytest.fixture(scope="session")
def podman(tmp_path_factory):
    missing = engine_missing()
    assert missing is None, missing
    with Podman(tmp_path_factory.mktemp("podman"), build_cache=container_base.build_cache()) as podman:
        yield podman


@pytest.fixture(scope="session")
def base_image(podman) -> str:
    return container_base.import_base(podman)


@pytest.fixture(scope="session")
def build_ca_bundle(tmp_path_factory) -> Path:
    """The machine's CA bundle with a line of this session's own, which `make image` hands to the build as its
    secret: a file that holds it in an image would be the secret kept."""
    paths = ssl.get_default_verify_paths()
    source = next(
        p for p in (os.environ.get("SSL_CERT_FILE"), paths.cafile, paths.openssl_cafile) if p and Path(p).is_file()
    )
    bundle = tmp_path_factory.mktemp("ca") / "ca-certificates.crt"
    bundle.write_bytes(Path(source).read_bytes() + f"# joshua test session {uuid.uuid4().hex}\n".encode())
    return bundle


def make_image(podman: Podman, ca_bundle: Path, base: str, context: Path, config: str, *overrides: str) -> str:
    """`make image` of a description into the session's storage; the tag it printed."""
    command = ["make", "--no-print-directory", "-o", "setup", "image", f"CONFIG={config}", f"BASE={base}"]
    command += [f"CONTEXT={context}"]
    if overrides:
        command.append(f"SET={' '.join(overrides)}")
    done = subprocess.run(
        command,
        cwd=ROOT,
        env=podman.environment({**os.environ, "SSL_CERT_FILE": str(ca_bundle)}),
        capture_output=True,
        text=True,
        timeout=BUILD_TIMEOUT_S,
    )
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-4000:]
    match = BUILT.search(done.stdout)
    assert match, done.stdout
    return match.group(1)


@pytest.fixture(scope="session")
def sim_image(podman, build_ca_bundle, base_image, tmp_path_factory) -> str:
    """The simulated arm, its dashboard reporting to the fleet view compose.yaml runs beside it (a robot starts
    whether or not a fleet view listens there). No C++ node: the image without the C++ build stage."""
    context = tmp_path_factory.mktemp("context") / "so100_sim"
    return make_image(podman, build_ca_bundle, base_image, context, "config/robots/so100_sim.pbtxt", FLEET_LINK)


@pytest.fixture(scope="session")
def servo_arm_image(podman, build_ca_bundle, base_image, tmp_path_factory) -> str:
    """The mock arm with its follower on a real STS3215 bus, run by its C++ binary: the image with the C++ stage."""
    context = tmp_path_factory.mktemp("context") / "servo_arm"
    return make_image(podman, build_ca_bundle, base_image, context, "config/robots/mock_arm.pbtxt", *SERVO_FOLLOWER)


@pytest.fixture
def netns():
    with NetworkNamespace(unique_name("joshua-test")) as namespace:
        yield namespace


@pytest.fixture
def containers(podman):
    """Names for this test's containers; each is removed (killed if need be) at teardown."""
    names = []

    def new_name(prefix: str) -> str:
        names.append(unique_name(prefix))
        return names[-1]

    yield new_name
    for name in names:
        podman.remove_container(name)
