"""fastdds_profile*.xml: the Fast DDS participant profiles nodes load (discovery timing; image transport)."""

from dataclasses import dataclass

from joshua_codegen.model import Process, Robot
from joshua_codegen.render import Context, template
from joshua_core import discovery as discovery_facts

PROFILE_PATH = "fastdds_profile.xml"  # processes that carry no images
IMAGES_PROFILE_PATH = "fastdds_profile_images.xml"  # processes that publish or subscribe images
PROFILE_PATHS = (PROFILE_PATH, IMAGES_PROFILE_PATH)
IMAGE_SEGMENT_BYTES = 16 * 1024 * 1024  # shared memory for a few 640x480 frames in flight


@dataclass(frozen=True)
class Discovery:
    """Participant discovery timing (Fast DDS defaults: 5 x 100 ms, then every 3 s, lease 20 s)."""

    initial_count: int = 10
    initial_period_ms: int = 100
    announcement_ms: int = 1000
    lease_ms: int = 10_000


def profile_path(process: Process) -> str:
    """The profile a process loads (its FASTRTPS_DEFAULT_PROFILES_FILE, relative to the output directory)."""
    return IMAGES_PROFILE_PATH if process.carries_images else PROFILE_PATH


@dataclass(frozen=True)
class ServerClient:
    """How a process reaches the robot's Discovery Server (Fast DDS 2.14 `discoveryServersList`).

    Every process is a SUPER_CLIENT: it learns every participant and endpoint the server knows, as tools
    that show the whole graph (the dashboard, joshua-topic, ros2 topic list) need; a robot's few dozen
    participants make the extra discovery traffic negligible. A client that has not reached its
    server yet asks again every announcement_ms."""

    address: str
    port: int
    prefix: str = discovery_facts.server_prefix()
    role: str = "SUPER_CLIENT"
    announcement_ms: int = 250  # Fast DDS's default: 450 ms


def emit(robot: Robot, context: Context) -> dict[str, str]:
    server = ServerClient(robot.discovery.address, robot.discovery.port) if robot.discovery else None
    return {
        path: template(
            "fastdds_profile.xml.j2",
            robot=robot,
            images=path == IMAGES_PROFILE_PATH,
            segment_size=IMAGE_SEGMENT_BYTES,
            discovery=Discovery(),
            server=server,
        )
        for path in PROFILE_PATHS
    }
