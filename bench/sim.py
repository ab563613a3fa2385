"""MuJoCo simulation speed: physics real-time factor alone, and while publishing and rendering.

    .venv/bin/python bench/sim.py [--seconds 10] [--quick]

1. physics alone: builtin:so100 stepped in this process as fast as possible (mj_step only), with
   the arm following a moving goal so that actuators and contacts do real work.
2. loaded, real time: a SIMULATION node process, started as a generated entrypoint starts it, at
   realtime_factor 1, simulating an ENCODER_PUBLISHER at 200 Hz and a CAMERA_PUBLISHER at 640x480,
   30 fps. This process subscribes to both topics (with the Fast DDS profile joshuac generates) and
   counts what arrives; the node's real-time factor, dropped time and frame counts come from the
   summary line it logs when it stops.
3. loaded, as fast as possible: the same at realtime_factor 0, which shows the headroom.
--quick: 0.5 s of physics alone and 1 s of the real-time run.
"""

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from support.described_nodes import compiled_settings, node_command, write_fastdds_profiles
from support.ros_env import bench_environment

ENCODER_RATE_HZ = 200.0
WIDTH, HEIGHT, CAMERA_RATE_HZ = 640, 480, 30.0
STATE_TOPIC, IMAGE_TOPIC = "/bench/joint_states", "/bench/image"
# The simulated robot; the engine's realtime_factor is set per run (`--set`). Servo ids 1-6 and
# SO-100 joint names are the encoder's defaults; QoS is each node type's default.
DESCRIPTION = f"""
robot_config {{
  name: "bench"
  mode: MODE_SIMULATION
  simulation {{ model: "builtin:so100" }}
  node {{
    name: "encoder"
    type: ENCODER_PUBLISHER
    topic_name: "{STATE_TOPIC}"
    rate_hz: {ENCODER_RATE_HZ}
  }}
  node {{
    name: "camera"
    type: CAMERA_PUBLISHER
    topic_name: "{IMAGE_TOPIC}"
    width: {WIDTH}
    height: {HEIGHT}
    rate_hz: {CAMERA_RATE_HZ}
  }}
}}
"""
PHYSICS_BATCH_STEPS = 100
STARTUP_TIMEOUT_S = 60.0
STOP_TIMEOUT_S = 10.0
SPIN_SLICE_S = 0.05
REALTIME_FACTORS = (1.0, 0.0)  # real time, then as fast as possible
SUMMARY = re.compile(
    r"simulated ([\d.]+) s in ([\d.]+) s \(real-time factor ([\d.]+)\), ([\d.]+) s dropped; "
    r"camera (\d+) frames \((\d+) skipped\)"
)


def physics_alone(seconds: float) -> float:
    """Real-time factor of mj_step alone on builtin:so100."""
    os.environ.setdefault("MUJOCO_GL", "egl")
    import math

    import mujoco

    from joshua_runtime.sim.model import load_model

    model = load_model("builtin:so100")
    data = mujoco.MjData(model)
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        phase = data.time
        data.ctrl[:] = [
            0.8 * math.sin(phase),
            0.3 + 0.3 * math.sin(0.7 * phase),
            0.3 * math.cos(phase),
            0.5 * math.sin(1.3 * phase),
            math.sin(phase),
            0.6 + 0.5 * math.sin(2 * phase),
        ]
        mujoco.mj_step(model, data, nstep=PHYSICS_BATCH_STEPS)
    return data.time / (time.perf_counter() - start)


def engine_settings(realtime_factor: float) -> dict:
    """Settings of the SIMULATION process standing in for the encoder and the camera."""
    settings = compiled_settings(DESCRIPTION, [f"simulation.realtime_factor={realtime_factor}"], "bench_sim.pbtxt")
    return settings["simulation"]


def loaded_run(engine: dict, seconds: float, env: dict) -> dict:
    """Run the node process for `seconds` while this process counts what it receives."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import Image, JointState

    process = subprocess.Popen(node_command(engine), env=env, stderr=subprocess.PIPE, text=True)
    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node("sim_bench", context=context)
    counts = {"state": 0, "image": 0}
    node.create_subscription(
        JointState, STATE_TOPIC, lambda _m: counts.__setitem__("state", counts["state"] + 1), QoSProfile(depth=10)
    )
    node.create_subscription(
        Image,
        IMAGE_TOPIC,
        lambda _m: counts.__setitem__("image", counts["image"] + 1),
        QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT),
    )
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    deadline = time.monotonic() + STARTUP_TIMEOUT_S
    while min(counts.values()) == 0 and time.monotonic() < deadline and process.poll() is None:
        executor.spin_once(timeout_sec=SPIN_SLICE_S)
    counts.update(state=0, image=0)
    start = time.monotonic()
    while time.monotonic() - start < seconds:
        executor.spin_once(timeout_sec=SPIN_SLICE_S)
    elapsed = time.monotonic() - start
    process.send_signal(signal.SIGINT)
    try:
        _, stderr = process.communicate(timeout=STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        _, stderr = process.communicate()
    executor.shutdown(timeout_sec=0)
    node.destroy_node()
    rclpy.shutdown(context=context)
    match = SUMMARY.search(stderr)
    if match is None:
        raise SystemExit(f"the simulation node did not report its run (exit {process.returncode}):\n{stderr}")
    sim_s, wall_s, factor, dropped, frames, skipped = match.groups()
    return {
        "factor": float(factor),
        "dropped": float(dropped),
        "frames": int(frames),
        "skipped": int(skipped),
        "wall": float(wall_s),
        "state_hz": counts["state"] / elapsed,
        "image_hz": counts["image"] / elapsed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="measurement time of each run")
    parser.add_argument("--quick", action="store_true", help="short runs at real time only (for the tests)")
    args = parser.parse_args()
    physics_s = 0.5 if args.quick else args.seconds
    args.seconds = 1.0 if args.quick else args.seconds
    engines = {factor: engine_settings(factor) for factor in REALTIME_FACTORS[: 1 if args.quick else None]}

    print(f"cores: {os.cpu_count()}  load average: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"physics alone (mj_step, builtin:so100, 2 ms step): real-time factor {physics_alone(physics_s):.1f}")

    with tempfile.TemporaryDirectory() as tmp:
        profile = write_fastdds_profiles(DESCRIPTION, Path(tmp), path="bench_sim.pbtxt")["simulation"]
        env = bench_environment("sim", FASTRTPS_DEFAULT_PROFILES_FILE=str(profile))
        os.environ.update(
            {k: env[k] for k in ("FASTRTPS_DEFAULT_PROFILES_FILE", "ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")}
        )
        print(
            f"loaded: JointState at {ENCODER_RATE_HZ:.0f} Hz + {WIDTH}x{HEIGHT} rgb8 at {CAMERA_RATE_HZ:.0f} fps, "
            f"{args.seconds:.0f} s per run, counted by a subscriber in this process"
        )
        print(
            f"{'realtime_factor':>15} {'reached':>8} {'dropped s':>9} {'frames':>7} {'skipped':>7} "
            f"{'states/s rx':>11} {'images/s rx':>11}"
        )
        for factor, engine in engines.items():
            r = loaded_run(engine, args.seconds, env)
            print(
                f"{factor:>15.1f} {r['factor']:>8.2f} {r['dropped']:>9.3f} {r['frames']:>7} {r['skipped']:>7} "
                f"{r['state_hz']:>11.1f} {r['image_hz']:>11.1f}"
            )


if __name__ == "__main__":
    sys.exit(main())
