"""fastdds_profile*.xml: the Fast DDS participant profiles nodes load (discovery timing; image transport)."""

from dataclasses import dataclass

from joshua_codegen.model import Process, Robot
from joshua_codegen.render import Context, template

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


def emit(robot: Robot, context: Context) -> dict[str, str]:
    return {
        path: template(
            "fastdds_profile.xml.j2",
            robot=robot,
            images=path == IMAGES_PROFILE_PATH,
            segment_size=IMAGE_SEGMENT_BYTES,
            discovery=Discovery(),
        )
        for path in PROFILE_PATHS
    }
