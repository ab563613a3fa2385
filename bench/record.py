"""DATA_SUBSCRIBER: time from start to ready, and sustained recording rate (frames per second written without drops).

    .venv/bin/python bench/record.py [--starts 3] [--seconds 8] [--cases 320x240@30,640x480@30,320x240@60] [--formats lerobot,parquet]
    .venv/bin/python bench/record.py --quick        # one start, one 1 s episode of 160x120 at 10 fps, lerobot

Start: the recorder process is started --starts times with nothing publishing; reported are the times
from its start to its ready line (READY=1) and to "dataset writer ready" (LeRobot imported in the
writer process), next to the time `import lerobot.datasets.lerobot_dataset` takes in a fresh Python
process in the same run (the floor of any recorder that imports LeRobot before it is ready).

For each case, MOCK_CAMERA_PUBLISHER (bgr8, best effort) and two MOCK_ENCODER_PUBLISHERs (leader
action and follower state, 6 joints) publish at the recording rate; a DATA_SUBSCRIBER process
records one episode of --seconds, then gets SIGINT and saves it. Reported: frames recorded,
frames expected at the nominal rate over the episode span, frames skipped (a stale input), the
achieved rate, the frames in the saved dataset (read back with LeRobotDataset), and the time from
SIGINT to exit (saving the episode; it must stay within the supervisor's 5 s SIGINT grace).
Every process loads the Fast DDS profile joshuac writes for it.
"""

import argparse
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from support.described_nodes import PYTHON, compiled_settings, node_command, write_fastdds_profiles
from support.ros_env import bench_environment

# Each case sets the image size, every node's rate and the recorder's output (`--set`). The
# encoders publish the SO-100's six joints; QoS is each node type's default.
DESCRIPTION = """
robot_config {
  name: "bench"
  mode: MODE_DATA_COLLECTION
  node { name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera/image_raw" }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }
  node { name: "follower" type: MOCK_ENCODER_PUBLISHER topic_name: "/follower/joint_states" }
  node {
    name: "recorder"
    type: DATA_SUBSCRIBER
    topic_name: "/leader/joint_states"
    input_topics: ["/camera/image_raw", "/follower/joint_states"]
  }
}
"""
RECORDER = "recorder"
STARTUP_TIMEOUT_S = 180.0
SAVE_TIMEOUT_S = 120.0
FIRST_FRAME = "first frame of the episode recorded"
READY = re.compile(r"\bready: recording")
WRITER_READY = re.compile(r"dataset writer ready")
LEROBOT_IMPORT = "import lerobot.datasets.lerobot_dataset"
STOPPED = re.compile(r"episode stopped after (\d+) frames \((\d+) skipped\) over ([\d.]+) s")
SAVED = re.compile(r"episode (\d+) saved: (\d+) frames")


def case_settings(case: str, output_format: str, workdir: Path) -> dict[str, dict]:
    """Settings of the publishers and the recorder of one case (`WIDTHxHEIGHT@FPS`), by node name."""
    width, height, rate = parse_case(case)
    output = workdir / f"{width}x{height}_{rate:g}_{output_format}"
    overrides = [
        f"camera.width={width}",
        f"camera.height={height}",
        *(f"{name}.rate_hz={rate}" for name in ("camera", "leader", "follower", RECORDER)),
        f"{RECORDER}.output_format={output_format}",
        f"{RECORDER}.output_directory={output}",
    ]
    return compiled_settings(DESCRIPTION, overrides, "bench_record.pbtxt")


class Process:
    """A node process whose output lines are collected; it loads the Fast DDS profile `profiles` names for it."""

    def __init__(self, settings: dict, env: dict, profiles: dict[str, Path]):
        env = dict(env, FASTRTPS_DEFAULT_PROFILES_FILE=str(profiles[settings["name"]]))
        self.popen = subprocess.Popen(
            node_command(settings), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
        )
        self.started = time.monotonic()
        self.lines: list[str] = []
        self.times: list[float] = []  # when each line arrived, seconds after the start
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        for line in self.popen.stdout:
            self.times.append(time.monotonic() - self.started)
            self.lines.append(line.rstrip())

    def seconds_until(self, pattern, timeout) -> float:
        """Seconds from the start to the first line matching `pattern`."""
        regex = re.compile(pattern) if isinstance(pattern, str) else pattern
        self.wait_for(regex, timeout)
        return next(t for t, line in zip(self.times, self.lines) if regex.search(line))

    def wait_for(self, pattern, timeout):
        regex = re.compile(pattern) if isinstance(pattern, str) else pattern
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for line in list(self.lines):
                found = regex.search(line)
                if found:
                    return found
            if self.popen.poll() is not None and not self.reader.is_alive():
                break
            time.sleep(0.02)
        raise RuntimeError(
            f"no {regex.pattern!r}:\n" + "\n".join(line for line in self.lines if not line.startswith("Svt["))
        )

    def stop(self):
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGINT)
        try:
            self.popen.wait(SAVE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.popen.kill()
            self.popen.wait()


def run_case(settings: dict[str, dict], seconds, env, profiles: dict[str, Path]) -> dict:
    camera, recording = settings["camera"], settings[RECORDER]
    rate = recording["rate_hz"]
    sensors = [Process(settings[name], env, profiles) for name in settings if name != RECORDER]
    recorder = Process(settings[RECORDER], env, profiles)
    try:
        recorder.wait_for(FIRST_FRAME, STARTUP_TIMEOUT_S)
        recorder.wait_for(WRITER_READY, STARTUP_TIMEOUT_S)  # the episode is saved, not lost, at SIGINT
        time.sleep(seconds)
        sent = time.monotonic()
        recorder.stop()
        exit_s = time.monotonic() - sent
        stopped = recorder.wait_for(STOPPED, 1.0)
        saved = recorder.wait_for(SAVED, 1.0)
    finally:
        for process in [recorder, *sensors]:
            process.stop()
    frames, skipped, span = int(stopped.group(1)), int(stopped.group(2)), float(stopped.group(3))
    return {
        "case": f"{camera['width']}x{camera['height']}@{rate:g} {recording['output_format']}",
        "frames": frames,
        "expected": round(span * rate) + 1,
        "skipped": skipped,
        "rate": (frames - 1) / span if span > 0 else 0.0,
        "saved": int(saved.group(2)),
        "loaded": loaded_frames(Path(recording["output_directory"]), env),
        "exit_s": exit_s,
    }


def startup(settings: dict[str, dict], env, profiles: dict[str, Path]) -> tuple[float, float]:
    """(seconds to the ready line, seconds to the writer's "ready") of one recorder start, nothing publishing."""
    recorder = Process(settings[RECORDER], env, profiles)
    try:
        ready = recorder.seconds_until(READY, STARTUP_TIMEOUT_S)
        writer = recorder.seconds_until(WRITER_READY, STARTUP_TIMEOUT_S)
    finally:
        recorder.stop()
    return ready, writer


def lerobot_import_s(env: dict) -> float:
    """Seconds a fresh Python process takes to import LeRobot's dataset module (interpreter start included)."""
    started = time.monotonic()
    subprocess.run([PYTHON, "-c", LEROBOT_IMPORT], env=env, check=True, capture_output=True)
    return time.monotonic() - started


def report_startup(settings: dict[str, dict], starts: int, env, profiles: dict[str, Path]) -> None:
    print(f"start -> ready of the recorder, {starts} starts (median); LeRobot's import in a fresh process alongside")
    ready, writer, imports = [], [], []
    for _ in range(starts):
        imports.append(lerobot_import_s(env))
        first, second = startup(settings, env, profiles)
        ready.append(first)
        writer.append(second)
    median_ready, median_writer, median_import = (statistics.median(v) for v in (ready, writer, imports))
    print(f"{'start -> ready (READY=1) s':<34} {median_ready:>8.2f}   (runs: {', '.join(f'{v:.2f}' for v in ready)})")
    print(
        f"{'start -> dataset writer ready s':<34} {median_writer:>8.2f}   (runs: {', '.join(f'{v:.2f}' for v in writer)})"
    )
    print(f"{'import of LeRobot alone s':<34} {median_import:>8.2f}   (runs: {', '.join(f'{v:.2f}' for v in imports)})")
    print(f"{'ready / LeRobot import':<34} {median_ready / median_import:>8.2f}x")
    print()


def loaded_frames(root: Path, env: dict) -> int:
    code = (
        "import sys; from lerobot.datasets.lerobot_dataset import LeRobotDataset; "
        f"print(len(LeRobotDataset('local/bench', root={str(root)!r}, video_backend='pyav')))"
    )
    result = subprocess.run([PYTHON, "-c", code], env=env, capture_output=True, text=True)
    return int(result.stdout.strip().splitlines()[-1]) if result.returncode == 0 else -1


def parse_case(text: str) -> tuple[int, int, float]:
    size, _, rate = text.partition("@")
    width, _, height = size.partition("x")
    return int(width), int(height), float(rate)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=3, help="recorder starts timed to their ready line")
    parser.add_argument("--seconds", type=float, default=8.0, help="length of the recorded episode")
    parser.add_argument("--cases", default="320x240@30,640x480@30,320x240@60", help="WIDTHxHEIGHT@FPS,...")
    parser.add_argument("--formats", default="lerobot,parquet", help="output formats to measure")
    parser.add_argument("--quick", action="store_true", help="one 1 s episode of 160x120@10, lerobot (for the tests)")
    args = parser.parse_args()
    if args.quick:
        args.starts, args.seconds, args.cases, args.formats = 1, 1.0, "160x120@10", "lerobot"
    with tempfile.TemporaryDirectory(prefix="joshua-bench-record-") as tmp:
        workdir = Path(tmp)
        profiles = write_fastdds_profiles(
            DESCRIPTION, workdir, [f"{RECORDER}.output_directory={workdir}"], "bench_record.pbtxt"
        )
        env = bench_environment("record", HF_HUB_OFFLINE="1", HF_DATASETS_CACHE=str(workdir / "hf-cache"))
        cases = [
            case_settings(case, output_format, workdir)
            for case in args.cases.split(",")
            for output_format in args.formats.split(",")
        ]
        report_startup(cases[0], args.starts, env, profiles)
        print(f"episode of {args.seconds:g} s per case; rate = (frames - 1) / span of the episode")
        print(
            f"{'case':<26} {'frames':>6} {'expected':>8} {'skipped':>7} {'rate fps':>8} {'saved':>6} "
            f"{'loaded':>6} {'SIGINT->exit s':>14}"
        )
        for settings in cases:
            r = run_case(settings, args.seconds, env, profiles)
            print(
                f"{r['case']:<26} {r['frames']:>6} {r['expected']:>8} {r['skipped']:>7} {r['rate']:>8.2f} "
                f"{r['saved']:>6} {r['loaded']:>6} {r['exit_s']:>14.2f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
