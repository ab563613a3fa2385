"""The robots of config/robots/ that run without hardware, each with a dashboard on a free port: in
simulation, of mock nodes, or with `joshua-emulate` standing in for their devices."""

import subprocess
import sys
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "config" / "robots"
CPP_BIN_DIR = ROOT / "build" / "bin"
EMULATOR = [sys.executable, "-m", "joshua_runtime.emulators.cli"]
SERVO_IDS = "1,2,3,4,5,6"
HUB_ADDRESS = "F4:B8:5E:00:00:01"  # the emulated hub's (joshua_runtime.emulators.pybricks)
VIDEO_WIDTH, VIDEO_HEIGHT, VIDEO_FRAMES = 160, 120, 20  # the video file the leader-follower camera reads
EMULATOR_STOP_TIMEOUT_S = 10


@dataclass(frozen=True)
class ConfigRobot:
    """A description of config/robots/ and how it runs here: `--set` overrides, and emulators to start
    first (`emulators(directory, stack) -> overrides`)."""

    config: str
    overrides: tuple[str, ...] = ()
    emulators: object = None

    @property
    def description(self) -> str:
        return (CONFIGS / f"{self.config}.pbtxt").read_text()


def _start(stack: ExitStack, argv: list[str]) -> str:
    """Start an emulator; return the first line it prints (once it serves)."""
    process = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    stack.callback(_stop, process)
    line = process.stdout.readline()
    assert process.poll() is None, f"{argv} exited: {line}{process.stdout.read()}"
    return line


def _stop(process: subprocess.Popen) -> None:
    process.terminate()
    try:
        process.wait(EMULATOR_STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def _leader_follower_devices(directory: Path, stack: ExitStack) -> list[str]:
    """Two emulated servo buses, a video file for the camera (which publishes it at the file's size, as a camera
    of that size would; scaled up to the description's 640x480, every frame cost the camera, the recorder, its
    PNG writer and the page 16 times the work), the recorder's dataset under `directory`."""
    leader, follower = directory / "ttyLEADER", directory / "ttyFOLLOWER"
    for link in (leader, follower):
        _start(stack, [*EMULATOR, "sts3215", "--ids", SERVO_IDS, "--link", str(link)])
    video = directory / "camera.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 10, (VIDEO_WIDTH, VIDEO_HEIGHT))
    for frame in range(VIDEO_FRAMES):
        writer.write(np.full((VIDEO_HEIGHT, VIDEO_WIDTH, 3), 10 * frame, np.uint8))
    writer.release()
    return [
        f"encoder_publisher.serial_port={leader}",
        f"actuator_subscriber.serial_port={follower}",
        f"camera_publisher.video_source={video}",
        f"camera_publisher.width={VIDEO_WIDTH}",
        f"camera_publisher.height={VIDEO_HEIGHT}",
        f"data_subscriber.output_directory={directory / 'episodes'}",
        f"cpp_bin_dir={CPP_BIN_DIR}",
    ]


def _pybricks_hub(directory: Path, stack: ExitStack) -> list[str]:
    """An emulated Pybricks hub behind an HCI on a free TCP port."""
    from dashboard_support import free_port

    port = free_port()
    _start(stack, [*EMULATOR, "pybricks", "--port", str(port)])
    return [f"base.ble_transport=tcp-client:127.0.0.1:{port}", f"base.hub={HUB_ADDRESS}"]


# Its recorder saves the episode in progress when it stops, and waits for its dataset writer to import LeRobot
# first: on a busy machine that outlasts the description's default graces (5 s + 2 s) at each of its stops,
# and the recorder ends by SIGKILL (its episode left for the next start to recover). The tests here are
# about the page's controls, not about graces or the recorder's saving: shorter graces end those waits sooner.
RECORDER_GRACES = ("shutdown.sigint_grace_s=2", "shutdown.sigterm_grace_s=1")

ROBOTS = {
    "so100_sim": ConfigRobot("so100_sim"),
    "mock_arm": ConfigRobot("mock_arm"),
    "lego_bot_simulated": ConfigRobot("lego_bot", ("mode=MODE_SIMULATION",)),
    "lego_bot_emulated_hub": ConfigRobot("lego_bot", emulators=_pybricks_hub),
    "so100_leader_follower_emulated": ConfigRobot(
        "so100_leader_follower", RECORDER_GRACES, emulators=_leader_follower_devices
    ),
}


@contextmanager
def devices(robot: ConfigRobot, directory: Path):
    """Start the robot's emulators; yields the `--set` overrides that point the robot at them."""
    with ExitStack() as stack:
        overrides = list(robot.overrides)
        if robot.emulators is not None:
            overrides += robot.emulators(directory, stack)
        yield overrides
