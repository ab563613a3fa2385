"""C++ and Python hardware nodes side by side: start-up, CPU, memory, stop time and teleop latency.

    .venv/bin/python bench/cpp_nodes.py [--samples 300] [--fast-rate-hz 1000] [--quick]

Every node runs against protocol-level emulators over real DDS (the STS3215 buses each in a process of
its own, whose replies wait on no thread of this one; an LDS-01 here), started as the generated
supervisor starts it: the Python entrypoint (`run_node(SETTINGS)`) or the C++ binary in build/bin with
its `--ros-args`, with a generated robot's Fast DDS profile (its discovery timing; Fast DDS's defaults
announce a new participant every 3 s after its first five, and a node's first scan then reached the
waiting subscriber up to 3 s late in half of the starts). One node at a time, per backend: seconds from
spawn to its first use of the device and to its first message, the CPU seconds used by then, CPU use
while running at its rate, PSS, and seconds from SIGINT to exit 0. Then leader -> follower latency (both
nodes of one backend, measured as bench/teleop.py does) at 200 Hz and at --fast-rate-hz, about what one
1 Mbaud bus allows: a SYNC_READ of six servos is ~0.9 ms on the wire. Last, the delay from SIGINT to
exit as a distribution: an idle follower per backend, started afresh --stop-trials times, SIGINT at a
random moment after its READY=1. The binaries are brought up to date with `make cpp` first (a no-op when
they are). --quick: 0.25 s of steady running, 200 Hz only, 20 samples, a 1 s rate window, 2 stops.
"""

import argparse
import os
import random
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from support.described_nodes import (
    CPP_BIN_DIR,
    ROOT,
    compiled_cpp_commands,
    compiled_settings,
    node_command,
)
from support.ros_env import bench_environment
from teleop import (
    HIGH_TICKS,
    LOW_TICKS,
    QUICK_RATE_WINDOW_S,
    QUICK_SAMPLES,
    RATE_WINDOW_S,
    SAMPLE_TIMEOUT_S,
    SETTLE_S,
    GoalWatch,
    ReadLog,
    percentile,
)

from joshua_codegen.emitters.fastdds import PROFILE_PATH
from joshua_codegen.emitters.process_launch import FASTDDS_PROFILE_VARIABLE
from joshua_runtime.drivers.sts3215_protocol import INST_SYNC_READ
from joshua_runtime.drivers.sts3215_table import register
from joshua_runtime.emulators.lds01 import Lds01Emulator
from joshua_runtime.emulators.sts3215_process import Sts3215EmulatorProcess

DESCRIPTION = """
robot_config {
  name: "bench_cpp"
  mode: MODE_TELEOPERATION
  node { name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" preferred_backend: CPP }
  node { name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" preferred_backend: CPP }
  node { name: "lidar" type: LIDAR_PUBLISHER topic_name: "/scan" preferred_backend: CPP }
}
"""
BACKENDS = ("Python", "C++")
STARTUP_TIMEOUT_S = 60.0
STOP_TIMEOUT_S = 5.0
STEADY_S, QUICK_STEADY_S = 5.0, 0.25  # a quick window still spans 25 ticks of a 100 Hz node
TORQUE_ENABLE_ADDRESS = register("Torque_Enable").address
TOPICS = {"leader": "/leader/joint_states", "lidar": "/scan"}  # what each node publishes
DEVICE_READY = ("leader", "follower")  # nodes whose first use of their bus the emulator sees
# The Fast DDS participant profile a generated robot's nodes without images load (its discovery timing), for
# the nodes and the subscriber here: first messages are what a robot's subscriber sees.
ROBOT_DISCOVERY_PROFILE = ROOT / "generated" / "mock_arm" / PROFILE_PATH
CLOCK_TICKS_PER_S = os.sysconf("SC_CLK_TCK")
STOP_TRIALS, QUICK_STOP_TRIALS = 20, 2
STOP_JITTER_S = 0.1  # SIGINT this long at most after READY=1, at a random moment


def commands(links: dict[str, Path], rate_hz: float) -> dict[str, dict[str, list[str]]]:
    """argv of each node by backend then name, with its device at `links[name]` and servo nodes at rate_hz."""
    overrides = [f"{name}.serial_port={link}" for name, link in links.items()]
    overrides += [f"leader.rate_hz={rate_hz}", f"follower.rate_hz={rate_hz}"]
    settings = compiled_settings(DESCRIPTION, overrides, "bench_cpp.pbtxt")
    return {
        "Python": {name: node_command(settings[name]) for name in links},
        "C++": compiled_cpp_commands(DESCRIPTION, overrides, "bench_cpp.pbtxt"),
    }


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S  # utime, stime


def pss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
        if line.startswith("Pss:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def stop(process: subprocess.Popen) -> tuple[int, float, str]:
    """SIGINT; (exit code, seconds until it exited, its stderr)."""
    sent = time.monotonic()
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        _, stderr = process.communicate(timeout=STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        _, stderr = process.communicate()
    return process.returncode, time.monotonic() - sent, stderr or ""


class FirstMessages:
    """An rclpy node spun in a thread, noting when the first message arrives on each watched topic."""

    def __init__(self):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.qos import qos_profile_sensor_data
        from sensor_msgs.msg import JointState, LaserScan

        rclpy.init()
        self.node = rclpy.create_node("bench_cpp_client")
        self.arrived: dict[str, float] = {}
        self.node.create_subscription(JointState, "/leader/joint_states", self._noter("/leader/joint_states"), 10)
        self.node.create_subscription(LaserScan, "/scan", self._noter("/scan"), qos_profile_sensor_data)
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def _noter(self, topic: str):
        return lambda _message: self.arrived.setdefault(topic, time.monotonic())

    def close(self) -> None:
        import rclpy

        self.executor.shutdown(timeout_sec=1)
        rclpy.shutdown()


def seconds(value: float | None) -> str:
    return "-" if value is None else f"{value:.3f}s"


def first_time(arrived: dict, key: str, process: subprocess.Popen) -> float | None:
    deadline = time.monotonic() + STARTUP_TIMEOUT_S
    while key not in arrived and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.002)
    return arrived.get(key)


def measure_node(
    name: str, argv: list[str], env: dict, client: FirstMessages, device_ready: dict, steady_s: float = STEADY_S
) -> dict:
    """Start-up, CPU, PSS and stop figures of one node run alone."""
    client.arrived.clear()
    device_ready.clear()
    started = time.monotonic()
    process = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    device = first_time(device_ready, name, process) if name in DEVICE_READY else None
    message = first_time(client.arrived, TOPICS[name], process) if name in TOPICS else None
    if (name in DEVICE_READY and device is None) or (name in TOPICS and message is None):
        raise SystemExit(f"{name} ({argv[0]}) did not start: {stop(process)[2]}")
    start_cpu = cpu_seconds(process.pid)
    time.sleep(steady_s)
    steady_cpu = (cpu_seconds(process.pid) - start_cpu) / steady_s if steady_s else 0.0
    pss = pss_mb(process.pid)
    code, stop_s, _ = stop(process)
    return {
        "device_s": device and device - started,
        "message_s": message and message - started,
        "start_cpu_s": start_cpu,
        "steady_cpu": steady_cpu,
        "pss_mb": pss,
        "exit": code,
        "stop_s": stop_s,
    }


def stop_delays(argv: list[str], env: dict, trials: int, jitter: random.Random) -> list[float]:
    """Seconds from SIGINT to exit 0 of `argv`, started afresh per trial and signalled at a random moment
    after it sent READY=1 (on a NOTIFY_SOCKET of this process, as the supervisor hands one)."""
    delays = []
    for trial in range(trials):
        name = f"joshua-bench-stop-{os.getpid()}-{trial}"
        with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as listener:
            listener.bind("\0" + name)
            listener.settimeout(STARTUP_TIMEOUT_S)
            process = subprocess.Popen(
                argv,
                env={**env, "NOTIFY_SOCKET": f"@{name}"},
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            try:
                while b"READY=1" not in listener.recv(4096):
                    pass
            except TimeoutError:
                raise SystemExit(f"{argv[0]} sent no READY=1: {stop(process)[2]}") from None
            time.sleep(jitter.random() * STOP_JITTER_S)
            code, seconds_taken, stderr = stop(process)
        if code != 0:
            raise SystemExit(f"{argv[0]} exited {code} on SIGINT: {stderr}")
        delays.append(seconds_taken)
    return delays


def teleop(
    argv: dict[str, list[str]], env: dict, leader_bus, follower_bus, rate_hz: float, samples: int, window_s: float
) -> dict:
    """Leader -> follower latency and loop rates of one backend's leader and follower (as bench/teleop.py)."""
    watch, reads = GoalWatch(), ReadLog()
    follower_bus.write_listeners.append(watch)
    leader_bus.packet_listeners.append(reads)
    for servo_id in leader_bus.ids:
        leader_bus.move_by_hand(servo_id, 2048)
    nodes = [
        subprocess.Popen(argv[name], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        for name in ("leader", "follower")
    ]
    jitter, period = random.Random(0), 1.0 / rate_hz
    latencies, waits, missed = [], [], 0
    try:
        if watch.wait_for(2048, STARTUP_TIMEOUT_S) is None:
            raise SystemExit(f"no goal reached the follower; node stderr: {[stop(node)[2] for node in nodes]}")
        reads_before, writes_before = len(reads.times), watch.writes
        time.sleep(window_s)
        read_rate = (len(reads.times) - reads_before) / window_s
        write_rate = (watch.writes - writes_before) / window_s
        for index in range(samples):
            goal = HIGH_TICKS if index % 2 == 0 else LOW_TICKS
            time.sleep(SETTLE_S + jitter.random() * period)
            moved_at = time.monotonic()
            leader_bus.move_by_hand(1, goal)
            arrived_at = watch.wait_for(goal, SAMPLE_TIMEOUT_S)
            if arrived_at is None:
                missed += 1
                continue
            # The leader's emulator reports its reads from a process of its own: the read that carried the
            # move may be reported after the follower's write was.
            if not leader_bus.wait_until(lambda at=moved_at: reads.first_after(at) is not None, SAMPLE_TIMEOUT_S):
                missed += 1
                continue
            latencies.append(1000 * (arrived_at - moved_at))
            waits.append(1000 * (reads.first_after(moved_at) - moved_at))
    finally:
        codes = [stop(node)[0] for node in nodes]
        follower_bus.write_listeners.remove(watch)
        leader_bus.packet_listeners.remove(reads)
    pipeline = [total - wait for total, wait in zip(latencies, waits)]
    return {
        "p50": percentile(latencies, 0.5),
        "p99": percentile(latencies, 0.99),
        "mean": statistics.fmean(latencies),
        "pipeline_p50": percentile(pipeline, 0.5),
        "pipeline_p99": percentile(pipeline, 0.99),
        "read_rate": read_rate,
        "write_rate": write_rate,
        "missed": missed,
        "codes": codes,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=300)
    parser.add_argument("--fast-rate-hz", type=float, default=1000.0)
    parser.add_argument("--stop-trials", type=int, default=STOP_TRIALS)
    parser.add_argument("--quick", action="store_true", help="a short run of every figure (for the tests)")
    args = parser.parse_args()
    stop_trials = QUICK_STOP_TRIALS if args.quick else args.stop_trials
    steady_s = QUICK_STEADY_S if args.quick else STEADY_S
    window_s = QUICK_RATE_WINDOW_S if args.quick else RATE_WINDOW_S
    samples = QUICK_SAMPLES if args.quick else args.samples
    rates = (200.0,) if args.quick else (200.0, args.fast_rate_hz)
    built = subprocess.run(["make", "--no-print-directory", "-s", "-C", str(ROOT / "cpp")], check=False)
    if built.returncode != 0:
        print(f"the C++ nodes do not build (make -C cpp); no binaries in {CPP_BIN_DIR}", file=sys.stderr)
        return 1
    load_before = os.getloadavg()[0]
    env = bench_environment("cpp_nodes", **{FASTDDS_PROFILE_VARIABLE: str(ROBOT_DISCOVERY_PROFILE)})
    os.environ.update(
        {key: env[key] for key in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE", FASTDDS_PROFILE_VARIABLE)}
    )
    with tempfile.TemporaryDirectory() as directory:
        links = {name: Path(directory) / f"tty{name.upper()}" for name in ("leader", "follower", "lidar")}
        leader_bus = Sts3215EmulatorProcess(links["leader"]).start()
        follower_bus = Sts3215EmulatorProcess(links["follower"]).start()
        lidar = Lds01Emulator(links["lidar"]).start()
        device_ready: dict[str, float] = {}
        leader_bus.packet_listeners.append(
            lambda packet, now: packet.code == INST_SYNC_READ and device_ready.setdefault("leader", now)
        )
        follower_bus.write_listeners.append(
            lambda _id, address, data, now: (
                address == TORQUE_ENABLE_ADDRESS and data[:1] == b"\x01" and device_ready.setdefault("follower", now)
            )
        )
        client = FirstMessages()
        try:
            node_argv = commands(links, 100.0)
            for backend in BACKENDS:  # warm the page cache: a cold first start is a disk figure, not a node's
                measure_node("leader", node_argv[backend]["leader"], env, client, device_ready, steady_s=0)
            nodes = {
                (name, backend): measure_node(name, node_argv[backend][name], env, client, device_ready, steady_s)
                for name in ("leader", "follower", "lidar")
                for backend in BACKENDS
            }
        finally:
            client.close()  # its callbacks would compete with the emulators for the GIL during teleop
        latency, stops = {}, {}
        try:
            for rate in rates:
                teleop_argv = commands(links, rate)
                for backend in BACKENDS:
                    latency[rate, backend] = teleop(
                        teleop_argv[backend], env, leader_bus, follower_bus, rate, samples, window_s
                    )
            jitter = random.Random(1)
            for backend in BACKENDS:
                stops[backend] = stop_delays(node_argv[backend]["follower"], env, stop_trials, jitter)
        finally:
            leader_bus.stop()
            follower_bus.stop()
            lidar.stop()
    print(f"load average while measuring: {load_before:.1f} -> {os.getloadavg()[0]:.1f} (2 cores)")
    print(
        "hardware nodes, one at a time on emulated devices (servo nodes at 100 Hz, lidar 5 turns/s); device "
        "ready: first SYNC_READ (leader), torque on (follower); first message: received by a subscriber "
        "that was waiting, so it includes DDS discovery, which a Python node's own start-up hides"
    )
    print(
        f"  {'node':<9} {'backend':<7} {'device ready':>12} {'first msg':>9} {'CPU-s then':>10} {'CPU running':>11} "
        f"{'PSS':>8} {'SIGINT->exit':>12}"
    )
    for (name, backend), r in nodes.items():
        print(
            f"  {name:<9} {backend:<7} {seconds(r['device_s']):>12} {seconds(r['message_s']):>9} "
            f"{r['start_cpu_s']:>9.2f}s {100 * r['steady_cpu']:>10.1f}% {r['pss_mb']:>6.1f}MB "
            f"{1000 * r['stop_s']:>9.0f} ms (exit {r['exit']})"
        )
    print(f"teleop leader -> follower over emulated 1 Mbaud buses, 6 servos, {samples} samples each")
    for (rate, backend), r in latency.items():
        print(
            f"  {rate:>6g} Hz {backend:<7} p50 {r['p50']:.2f} ms, p99 {r['p99']:.2f} ms, mean {r['mean']:.2f} ms "
            f"(read -> goal p50 {r['pipeline_p50']:.2f} ms, p99 {r['pipeline_p99']:.2f} ms); "
            f"{r['read_rate']:.0f} leader transactions/s, {r['write_rate']:.0f} goal writes/s; "
            f"{r['missed']} missed; exit codes {r['codes']}"
        )
    print(f"SIGINT -> exit 0 of an idle follower, {stop_trials} fresh starts per backend, signal at a random moment")
    for backend, delays in stops.items():
        ms = [1000 * delay for delay in delays]
        print(
            f"  {backend:<7} min {min(ms):.1f} ms, p50 {percentile(ms, 0.5):.1f} ms, p90 {percentile(ms, 0.9):.1f} ms, "
            f"max {max(ms):.1f} ms, spread p90-min {percentile(ms, 0.9) - min(ms):.1f} ms"
        )
    ratio = percentile(stops["C++"], 0.5) / percentile(stops["Python"], 0.5)
    print(f"  C++ p50 / Python p50: {ratio:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
