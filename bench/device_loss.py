"""How fast each device node reports a device that stops answering, against the 2 s every node promises.

    .venv/bin/python bench/device_loss.py [--runs 3] [--quick]

Each case starts a node process on an emulated device, waits for its data, injects the fault and
times the node's report: the first line it writes on stderr about the loss (a log line, or the
error line it exits 3 with). Cases: the LEGO base with `joshua-emulate pybricks` killed (a dongle
pulled out: the controller's connection closes) and frozen (SIGSTOP: nothing closes, nothing
answers), then how long after the emulator came back its /odom resumes; the LDS-01 lidar (Python
and C++) whose emulated motor stalls; the camera whose MJPEG stream stalls; the servo encoder
(Python and C++) whose bus disappears. Prints, per case, the median and largest time and the
largest as a fraction of DEVICE_REPORT_S. --quick: one run per case.
"""

import argparse
import re
import signal
import statistics
import subprocess
import tempfile
import threading
import time
from pathlib import Path

from support.described_nodes import ROOT, compiled_cpp_commands, compiled_settings, node_command
from support.ros_env import bench_environment

from joshua_core.device_link import DEVICE_REPORT_S
from joshua_runtime.emulators.lds01 import Lds01Emulator
from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from testsupport.hub_emulator import HubEmulator
from testsupport.mjpeg_server import MjpegServer

STARTUP_TIMEOUT_S = 40.0
REPORT_TIMEOUT_S = 20.0
STOP_TIMEOUT_S = 10.0
LEGO = (ROOT / "config" / "robots" / "lego_bot.pbtxt").read_text()
HUB_LOST = r"link to Pybricks hub .* lost \("
HUB_BACK = r"reconnected to Pybricks hub"
ONE_NODE = """
robot_config {{
  name: "bench"
  mode: MODE_TELEOPERATION
  node {{ name: "device" type: {type} preferred_backend: {backend} topic_name: "/data" {fields} }}
}}
"""


class Node:
    """A node process whose stderr lines are kept with the time each arrived."""

    def __init__(self, argv: list[str], env: dict):
        self.lines: list[tuple[float, str]] = []
        self.process = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.process.stderr:
            self.lines.append((time.monotonic(), line.rstrip()))

    def wait_line(self, pattern: str, timeout_s: float, after: float = 0.0) -> float:
        """When the first line matching `pattern` (arriving after `after`) came."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            for at, line in list(self.lines):
                if at >= after and re.search(pattern, line):
                    return at
            time.sleep(0.005)
        text = "\n".join(line for _, line in self.lines)
        raise SystemExit(f"no line matching {pattern!r} within {timeout_s:g} s:\n{text}")

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def hub_case(directory: Path, env: dict, fault: str) -> tuple[float, ...]:
    """(seconds to the loss report[, seconds from the emulator serving again to the reconnection]) for `fault`."""
    hub = HubEmulator(directory).start()
    base = Node(node_command(compiled_settings(LEGO, [f"base.ble_transport={hub.hci}"])["base"]), env)
    try:
        base.wait_line(r"\]: ready: ", STARTUP_TIMEOUT_S)
        time.sleep(0.5)
        if fault == "frozen":
            faulted = time.monotonic()
            hub.pause()
            reported = base.wait_line(HUB_LOST, REPORT_TIMEOUT_S, faulted)
            return (reported - faulted,)
        faulted = time.monotonic()
        hub.stop(signal.SIGKILL)
        reported = base.wait_line(HUB_LOST, REPORT_TIMEOUT_S, faulted)
        hub.start()
        back = time.monotonic()  # the emulator serves its HCI again
        reconnected = base.wait_line(HUB_BACK, REPORT_TIMEOUT_S, back)
        return reported - faulted, reconnected - back
    finally:
        base.stop()
        hub.stop()


def node_argv(node_type: str, fields: str, backend: str, port: Path) -> list[str]:
    """The command of one node of `node_type` on `port`, as the supervisor runs it with `backend` (py or cpp)."""
    text = ONE_NODE.format(type=node_type, fields=fields, backend="CPP" if backend == "cpp" else "PYTHON")
    overrides = [f"device.serial_port={port}"]
    if backend == "cpp":
        return compiled_cpp_commands(text, overrides)["device"]
    return node_command(compiled_settings(text, overrides)["device"])


def lidar_case(directory: Path, env: dict, backend: str) -> tuple[float]:
    with Lds01Emulator(directory / f"ttyLIDAR-{backend}") as lidar:
        node = Node(node_argv("LIDAR_PUBLISHER", "", backend, lidar.link), env)
        try:
            node.wait_line(r"\]: ready: ", STARTUP_TIMEOUT_S)
            faulted = time.monotonic()
            lidar.stream.spinning = False
            return (node.wait_line(r": error: .*stopped streaming", REPORT_TIMEOUT_S, faulted) - faulted,)
        finally:
            node.stop()


def camera_case(env: dict) -> tuple[float]:
    with MjpegServer(period_s=0.1) as camera:  # slower than the node asks: no frame waits in a buffer
        settings = compiled_settings(
            f'robot_config {{ name: "bench" mode: MODE_TELEOPERATION node {{ name: "camera" type: CAMERA_PUBLISHER '
            f'topic_name: "/image" video_source: "{camera.url}" width: 160 height: 120 rate_hz: 20 }} }}'
        )["camera"]
        node = Node(node_command(settings), env)
        try:
            node.wait_line(r"\]: ready: ", STARTUP_TIMEOUT_S)
            time.sleep(0.5)
            camera.stall()
            reported = node.wait_line(r": error: .*stopped delivering frames", REPORT_TIMEOUT_S, camera.stopped_at)
            return (reported - camera.stopped_at,)
        finally:
            node.stop()


def encoder_case(directory: Path, env: dict, backend: str) -> tuple[float]:
    bus = Sts3215Emulator(directory / f"ttyBUS-{backend}", [1, 2, 3, 4, 5, 6]).start()
    node = Node(node_argv("ENCODER_PUBLISHER", "device_ids: [1, 2, 3, 4, 5, 6]", backend, bus.link), env)
    try:
        node.wait_line(r"\]: ready: ", STARTUP_TIMEOUT_S)
        faulted = time.monotonic()
        bus.stop()
        return (node.wait_line(rf"\[WARN\].*{re.escape(str(bus.link))}", REPORT_TIMEOUT_S, faulted) - faulted,)
    finally:
        node.stop()
        bus.stop()


def describe(label: str, samples: list[float]) -> None:
    worst = max(samples)
    print(
        f"{label}: median {statistics.median(samples) * 1000:.0f} ms, largest {worst * 1000:.0f} ms "
        f"= {worst / DEVICE_REPORT_S:.2f} of {DEVICE_REPORT_S:g} s ({len(samples)} runs)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each case")
    parser.add_argument("--quick", action="store_true", help="one run of each case")
    args = parser.parse_args()
    runs = 1 if args.quick else args.runs
    env = bench_environment("device_loss")
    with tempfile.TemporaryDirectory() as temporary:
        directory = Path(temporary)
        killed = [hub_case(directory, env, "killed") for _ in range(runs)]
        describe("LEGO base, hub emulator killed: loss reported", [times[0] for times in killed])
        describe(
            "LEGO base, hub emulator frozen: loss reported",
            [hub_case(directory, env, "frozen")[0] for _ in range(runs)],
        )
        print(
            f"LEGO base, hub emulator back: reconnected after median "
            f"{statistics.median(times[1] for times in killed) * 1000:.0f} ms"
        )
        for backend in ("py", "cpp"):
            describe(
                f"lidar ({backend}), motor stalled: reported",
                [lidar_case(directory, env, backend)[0] for _ in range(runs)],
            )
        describe("camera (py), stream stalled: reported", [camera_case(env)[0] for _ in range(runs)])
        for backend in ("py", "cpp"):
            describe(
                f"servo encoder ({backend}), bus gone: reported",
                [encoder_case(directory, env, backend)[0] for _ in range(runs)],
            )


if __name__ == "__main__":
    main()
