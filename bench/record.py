"""Sustained recording rate of the DATA_SUBSCRIBER node: frames per second written without drops.

    .venv/bin/python bench/record.py [--seconds 8] [--cases 320x240@30,640x480@30,320x240@60] [--formats lerobot,parquet]

For each case, MOCK_CAMERA_PUBLISHER (bgr8, best effort) and two MOCK_ENCODER_PUBLISHERs (leader
action and follower state, 6 joints) publish at the recording rate; a DATA_SUBSCRIBER process
records one episode of --seconds, then gets SIGINT and saves it. Reported: frames recorded,
frames expected at the nominal rate over the episode span, frames skipped (a stale input), the
achieved rate, the frames in the saved dataset (read back with LeRobotDataset), and the time from
SIGINT to exit (saving the episode; it must stay within the supervisor's 5 s SIGINT grace).
Every process loads the Fast DDS profile joshuac generates (large shared-memory segment).
"""

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PYTHON = str(ROOT / ".venv" / "bin" / "python")
JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
SENSOR = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}
STARTUP_TIMEOUT_S = 180.0
SAVE_TIMEOUT_S = 120.0
FIRST_FRAME = "first frame of the episode recorded"
STOPPED = re.compile(r"episode stopped after (\d+) frames \((\d+) skipped\) over ([\d.]+) s")
SAVED = re.compile(r"episode (\d+) saved: (\d+) frames")


def settings(name, node_type, **values) -> dict:
    base = {
        "robot": "bench", "mode": "MODE_DATA_COLLECTION", "name": name, "type": node_type, "topic": None,
        "state_topic": None, "inputs": [], "qos": RELIABLE, "serial_port": "", "baud_rate": 0, "device_ids": [],
        "joint_names": [], "calibration_file": "", "camera_index": -1, "video_source": "", "width": 640,
        "height": 480, "rate_hz": 30.0, "frame_id": "base_link", "model_path": "", "policy_type": "",
        "device": "cpu", "output_format": "lerobot", "output_directory": "", "simulation": None,
    }
    base.update(values)
    return base


class Process:
    """A node process whose output lines are collected."""

    def __init__(self, node_settings: dict, env: dict):
        code = f"from joshua_runtime.entrypoint import run_node; import sys; sys.exit(run_node({node_settings!r}))"
        self.popen = subprocess.Popen([PYTHON, "-c", code], env=env, stdout=subprocess.PIPE,
                                      stderr=subprocess.STDOUT, text=True)
        self.lines: list[str] = []
        self.reader = threading.Thread(target=lambda: self.lines.extend(line.rstrip() for line in self.popen.stdout),
                                       daemon=True)
        self.reader.start()

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
        raise RuntimeError(f"no {regex.pattern!r}:\n" + "\n".join(l for l in self.lines if not l.startswith("Svt[")))

    def stop(self):
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGINT)
        try:
            self.popen.wait(SAVE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.popen.kill()
            self.popen.wait()


def run_case(width, height, rate, output_format, seconds, env, workdir) -> dict:
    output = workdir / f"{width}x{height}_{rate:g}_{output_format}"
    camera = {"name": "/camera/image_raw", "message_type": "sensor_msgs/msg/Image", "qos": SENSOR}
    leader = {"name": "/leader/joint_states", "message_type": "sensor_msgs/msg/JointState", "qos": RELIABLE}
    follower = {"name": "/follower/joint_states", "message_type": "sensor_msgs/msg/JointState", "qos": RELIABLE}
    sensors = [
        Process(settings("camera", "MOCK_CAMERA_PUBLISHER", width=width, height=height, rate_hz=rate, topic=camera), env),
        Process(settings("leader", "MOCK_ENCODER_PUBLISHER", joint_names=JOINTS, rate_hz=rate, topic=leader), env),
        Process(settings("follower", "MOCK_ENCODER_PUBLISHER", joint_names=JOINTS, rate_hz=rate, topic=follower), env),
    ]
    recorder = Process(settings(
        "recorder", "DATA_SUBSCRIBER", rate_hz=rate, output_directory=str(output), output_format=output_format,
        topic=leader, inputs=[camera, follower],
    ), env)
    try:
        recorder.wait_for(FIRST_FRAME, STARTUP_TIMEOUT_S)
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
        "case": f"{width}x{height}@{rate:g} {output_format}", "frames": frames, "expected": round(span * rate) + 1,
        "skipped": skipped, "rate": (frames - 1) / span if span > 0 else 0.0, "saved": int(saved.group(2)),
        "loaded": loaded_frames(output, env), "exit_s": exit_s,
    }


def loaded_frames(root: Path, env: dict) -> int:
    code = ("import sys; from lerobot.datasets.lerobot_dataset import LeRobotDataset; "
            f"print(len(LeRobotDataset('local/bench', root={str(root)!r}, video_backend='pyav')))")
    result = subprocess.run([PYTHON, "-c", code], env=env, capture_output=True, text=True)
    return int(result.stdout.strip().splitlines()[-1]) if result.returncode == 0 else -1


def parse_case(text: str) -> tuple[int, int, float]:
    size, _, rate = text.partition("@")
    width, _, height = size.partition("x")
    return int(width), int(height), float(rate)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=8.0, help="length of the recorded episode")
    parser.add_argument("--cases", default="320x240@30,640x480@30,320x240@60", help="WIDTHxHEIGHT@FPS,...")
    parser.add_argument("--formats", default="lerobot,parquet", help="output formats to measure")
    args = parser.parse_args()
    from joshua_codegen.render import template

    with tempfile.TemporaryDirectory(prefix="joshua-bench-record-") as tmp:
        workdir = Path(tmp)
        profile = workdir / "fastdds_profile.xml"
        profile.write_text(template("fastdds_profile.xml.j2"))
        env = dict(os.environ, PYTHONUNBUFFERED="1", HF_HUB_OFFLINE="1", HF_DATASETS_CACHE=str(workdir / "hf-cache"),
                   ROS_DOMAIN_ID=str(zlib.crc32(b"bench/record") % 100 + 120),
                   ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", FASTRTPS_DEFAULT_PROFILES_FILE=str(profile))
        print(f"episode of {args.seconds:g} s per case; rate = (frames - 1) / span of the episode")
        print(f"{'case':<26} {'frames':>6} {'expected':>8} {'skipped':>7} {'rate fps':>8} {'saved':>6} "
              f"{'loaded':>6} {'SIGINT->exit s':>14}")
        for text in args.cases.split(","):
            for output_format in args.formats.split(","):
                r = run_case(*parse_case(text), output_format, args.seconds, env, workdir)
                print(f"{r['case']:<26} {r['frames']:>6} {r['expected']:>8} {r['skipped']:>7} {r['rate']:>8.2f} "
                      f"{r['saved']:>6} {r['loaded']:>6} {r['exit_s']:>14.2f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
