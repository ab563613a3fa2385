"""Discovery time (process start -> node visible on the ROS graph) and memory (PSS) per node process.

    .venv/bin/python bench/discovery.py [--sizes 1,8,32] [--runs 2] [--quick]

For each size N, N MOCK_ENCODER_PUBLISHER node processes start at once, as generated entrypoints
start them, with the Fast DDS profile joshuac gives them. An observer process started before them
records when each node appears in its graph (`get_node_names`); once all are up, a second observer
starts and records how long it takes to see all N. Each node prints the moment its imports are done
(just before rclpy.init), so "discovery" is the time from there to visible, without Python's start.
Then the same nodes as a built robot, started by its supervisor.py: from the supervisor's start to every node
visible, its Python nodes forked from the node starter and, for comparison, each in an interpreter of its own
(--no-node-starter), with the CPU-s a node had used by then; the goal is all 32 visible within GOAL_S, the max
over the runs. The peer, in turn with them: N C++ nodes of the same shape (cpp/bench/graph_node.cpp, on the C++
nodes' joshua_rcl, one JointState publisher) spawned at once, from the first spawn to all visible: what DDS
discovery costs on this machine without Python and without a supervisor. Every case runs as the machine is ("quiet") and under load (one busy-looping burner process per
core, at the nodes' priority, started and stopped here); "unseen" counts nodes an observer had not seen after
OBSERVE_TIMEOUT_S. Then PSS per node (/proc/PID/smaps_rollup) of N running nodes, with the profile of processes
that carry images (large shared-memory segment) and with the profile of the others.
"""

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from support import graph_peer
from support.described_nodes import PYTHON, compiled_settings, write_fastdds_profiles
from support.process_usage import cpu_seconds
from support.ros_env import bench_environment

from joshua_codegen.emitters.fastdds import IMAGES_PROFILE_PATH
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.supervisor.containment import children_of
from joshua_codegen.write import write_tree
from joshua_core.schema import RobotDescription

NAME = "disc"
OBSERVER_POLL_S = 0.005
OBSERVE_TIMEOUT_S = 60.0  # a node not seen by then counts as unseen
STOP_TIMEOUT_S = 10.0
GOAL_S = 1.5  # 32 Python nodes visible on the graph within this of the supervisor's start, on 2 cores
RATE_HZ = 5.0  # of every node's JointState
IMPORTED = "imported at "
READY, SEEN = "starting at ", "seen "
# The node process: the generated entrypoint's call, with the moment its imports end printed first.
NODE_CODE = """import sys, time
import rclpy
from joshua_runtime.entrypoint import run_node, node_class
node_class({node_type!r})
print("{imported}" + repr(time.monotonic()), flush=True)
sys.exit(run_node({settings!r}))
"""


def description(count: int) -> str:
    nodes = "\n".join(
        f'  node {{ name: "{NAME}{i:02d}" type: MOCK_ENCODER_PUBLISHER topic_name: "/{NAME}{i:02d}/joints" '
        f"rate_hz: {RATE_HZ:g} }}"
        for i in range(count)
    )
    return f'robot_config {{\n  name: "bench_discovery"\n  mode: MODE_TELEOPERATION\n{nodes}\n}}\n'


def observe(expected: int, timeout_s: float) -> int:
    """Observer process: print when it starts its participant, then each node named NAME* when first seen."""
    import rclpy

    print(f"{READY}{time.monotonic()!r}", flush=True)
    rclpy.init()
    node = rclpy.create_node(f"observer_{os.getpid()}")
    seen: set[str] = set()
    deadline = time.monotonic() + timeout_s
    while len(seen) < expected and time.monotonic() < deadline:
        for name in node.get_node_names():
            if name.startswith(NAME) and name not in seen:
                seen.add(name)
                print(f"{SEEN}{name} {time.monotonic()!r}", flush=True)
        time.sleep(OBSERVER_POLL_S)
    node.destroy_node()
    rclpy.shutdown()
    return 0 if len(seen) == expected else 1


class Lines:
    """A process whose stdout lines are collected by a thread."""

    def __init__(self, command: list[str], env: dict):
        self.popen = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.lines: list[str] = []
        self.reader = threading.Thread(
            target=lambda: self.lines.extend(line.rstrip() for line in self.popen.stdout), daemon=True
        )
        self.reader.start()

    def collect(self, prefix: str, count: int = 1, timeout_s: float = OBSERVE_TIMEOUT_S) -> list[str]:
        """The lines starting with `prefix`, once there are `count` of them, the process ended or time ran out."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            found = [line for line in list(self.lines) if line.startswith(prefix)]
            if len(found) >= count or (self.popen.poll() is not None and not self.reader.is_alive()):
                return found
            time.sleep(0.01)
        return [line for line in list(self.lines) if line.startswith(prefix)]

    def wait_for(self, prefix: str) -> str:
        found = self.collect(prefix)
        if not found:
            raise SystemExit(f"no line {prefix!r} from {self.popen.args[:2]}:\n" + "\n".join(self.lines[-20:]))
        return found[0]

    def stop(self) -> None:
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGINT)
        try:
            self.popen.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.popen.kill()
            self.popen.wait()
        self.reader.join(STOP_TIMEOUT_S)


def start_observer(expected: int, env: dict) -> tuple[Lines, float]:
    observer = Lines([PYTHON, __file__, "--observe", str(expected)], env)
    return observer, float(observer.wait_for(READY)[len(READY) :])


def seen_times(observer: Lines, expected: int) -> dict[str, float]:
    """When the observer saw each node; a node it did not see within OBSERVE_TIMEOUT_S is left out."""
    lines = observer.collect(SEEN, expected)
    return {name: float(moment) for name, moment in (line[len(SEEN) :].split() for line in lines)}


def start_nodes(settings: dict[str, dict], env: dict) -> dict[str, tuple[Lines, float]]:
    nodes = {}
    for name, node in settings.items():
        code = NODE_CODE.format(node_type=node["type"], imported=IMPORTED, settings=node)
        nodes[name] = (Lines([PYTHON, "-c", code], env), time.monotonic())
    return nodes


def run_case(count: int, env: dict) -> dict[str, list[float]]:
    """Seconds, per node: spawn -> visible and imports done -> visible (observer before), and
    rclpy.init -> all visible (observer after)."""
    settings = compiled_settings(description(count), path="bench_discovery.pbtxt")
    before, _ = start_observer(count, env)
    nodes = start_nodes(settings, env)
    try:
        seen = seen_times(before, count)
        imported = {name: float(process.wait_for(IMPORTED)[len(IMPORTED) :]) for name, (process, _) in nodes.items()}
        after, after_ready = start_observer(count, env)
        seen_after = seen_times(after, count)
        after.stop()
    finally:
        before.stop()
        for process, _ in nodes.values():
            process.stop()
    return {
        "spawn": [seen[name] - spawned for name, (_, spawned) in nodes.items() if name in seen],
        "discovery": [seen[name] - imported[name] for name in nodes if name in seen],
        "after": [max(seen_after.values()) - after_ready] if len(seen_after) == count else [],
        "missed": [count - len(seen) + count - len(seen_after)],
    }


def node_cpu_s(supervisor: int) -> list[float]:
    """CPU-s so far (user + system, all threads) of each node the supervisor runs (its children running a node)."""
    spent = []
    for child in children_of(supervisor):
        try:
            if f"/nodes/{NAME}".encode() in Path(f"/proc/{child}/cmdline").read_bytes():
                spent.append(cpu_seconds(child))
        except OSError:  # gone meanwhile
            continue
    return spent


def supervised_visible_s(count: int, env: dict, directory: Path, starter: bool) -> tuple[float | None, float]:
    """Seconds from the supervisor's start to all `count` nodes visible (None: some never were), and the mean
    CPU-s a node had used by then (nan: no node process was found)."""
    from google.protobuf import text_format

    out = directory / f"robot{count}"
    if not out.exists():
        write_tree(render(plan(text_format.Parse(description(count), RobotDescription()), "disc.pbtxt")), out)
    observer, _ = start_observer(count, env)
    command = [PYTHON, str(out / "supervisor.py"), "--no-control", "--log-dir", str(directory / "logs")]
    supervisor = Lines(command + ([] if starter else ["--no-node-starter"]), env)
    started = time.monotonic()
    try:
        seen = seen_times(observer, count)
        spent = node_cpu_s(supervisor.popen.pid)
    finally:
        observer.stop()
        supervisor.stop()
    return (max(seen.values()) - started if len(seen) == count else None), (
        statistics.fmean(spent) if spent else float("nan")
    )


def peer_visible_s(count: int, env: dict) -> tuple[float | None, float]:
    """Seconds from spawning `count` C++ peer nodes at once to all visible (None: some never were), and the mean
    CPU-s a node had used by then."""
    observer, _ = start_observer(count, env)
    started = time.monotonic()
    nodes = [Lines(graph_peer.command(f"{NAME}{i:02d}", f"/{NAME}{i:02d}/joints", RATE_HZ), env) for i in range(count)]
    try:
        seen = seen_times(observer, count)
        spent = [cpu_seconds(node.popen.pid) for node in nodes]
    finally:
        observer.stop()
        for node in nodes:
            node.stop()
    return (max(seen.values()) - started if len(seen) == count else None), statistics.fmean(spent)


def ratio(numerator: float | None, denominator: float | None) -> str:
    return "-" if numerator is None or denominator is None else f"{numerator / denominator:.2f}"


def supervised_cases(sizes: list[int], runs: int, env: dict, directory: Path) -> None:
    print(f"supervisor.py start -> all visible, seconds, max of {runs} run(s); goal for 32 nodes: {GOAL_S} s;")
    print("Python nodes forked from the node starter / each in its own interpreter; the peer: C++ nodes spawned")
    print("at once. Ratios: own interpreter / starter, starter / C++. CPU-s a node used by then (mean): the same three")
    print(
        f"{'load':<6} {'nodes':>5} {'node starter':>13} {'own interpreter':>16} {'C++ peer':>9} "
        f"{'own/starter':>12} {'starter/C++':>12} {'CPU-s/node':>19}"
    )
    variants = ("starter", "own", "peer")
    for busy in (False, True):
        for count in sizes:
            times, cpu = {key: [] for key in variants}, {key: [] for key in variants}
            with cpu_load(busy):
                for _ in range(runs):
                    for variant in variants:  # taking turns, so that all see the same machine
                        if variant == "peer":
                            seconds, node_cpu = peer_visible_s(count, env)
                        else:
                            seconds, node_cpu = supervised_visible_s(count, env, directory, variant == "starter")
                        times[variant].append(seconds)
                        cpu[variant].append(node_cpu)
            worst = {key: None if None in values else max(values) for key, values in times.items()}
            shown = {key: "unseen" if value is None else f"{value:.2f}" for key, value in worst.items()}
            spent = " / ".join(f"{statistics.fmean(cpu[key]):.2f}" for key in variants)
            print(
                f"{'busy' if busy else 'quiet':<6} {count:>5} {shown['starter']:>13} {shown['own']:>16} "
                f"{shown['peer']:>9} {ratio(worst['own'], worst['starter']):>12} "
                f"{ratio(worst['starter'], worst['peer']):>12} {spent:>19}",
                flush=True,
            )


@contextmanager
def cpu_load(busy: bool):
    """One busy-looping process per core while the block runs (none when not `busy`)."""
    burners = [
        subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(os.cpu_count() if busy else 0)
    ]
    try:
        yield
    finally:
        for burner in burners:
            burner.kill()
            burner.wait()


def pss_kib(pid: int) -> int:
    for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
        if line.startswith("Pss:"):
            return int(line.split()[1])
    raise SystemExit(f"no Pss line in /proc/{pid}/smaps_rollup")


def pss_per_node(count: int, env: dict) -> float:
    """Mean PSS in MiB of `count` running node processes, once all are visible."""
    settings = compiled_settings(description(count), path="bench_discovery.pbtxt")
    observer, _ = start_observer(count, env)
    nodes = start_nodes(settings, env)
    try:
        seen_times(observer, count)
        return statistics.fmean(pss_kib(process.popen.pid) for process, _ in nodes.values()) / 1024
    finally:
        observer.stop()
        for process, _ in nodes.values():
            process.stop()


def summary(values: list[float]) -> str:
    return f"{statistics.median(values):6.2f} / {max(values):6.2f}" if values else "none seen"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1,8,32", help="node counts, comma-separated")
    parser.add_argument("--runs", type=int, default=2, help="runs of each case")
    parser.add_argument("--quick", action="store_true", help="one run of 2 nodes (seconds, for the tests)")
    parser.add_argument("--observe", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.observe is not None:
        return observe(args.observe, OBSERVE_TIMEOUT_S)
    sizes, runs = ([2], 1) if args.quick else ([int(size) for size in args.sizes.split(",")], args.runs)
    graph_peer.build()
    with tempfile.TemporaryDirectory(prefix="joshua-bench-discovery-") as tmp:
        profiles = write_fastdds_profiles(description(1), Path(tmp), path="bench_discovery.pbtxt")
        plain = profiles[f"{NAME}00"]
        images = Path(tmp) / IMAGES_PROFILE_PATH
        env = bench_environment("discovery", FASTRTPS_DEFAULT_PROFILES_FILE=str(plain))
        print(
            f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}, ROS_DOMAIN_ID {env['ROS_DOMAIN_ID']}, "
            f"{runs} run(s) per case, profile {plain.name}; seconds, median / max over nodes and runs"
        )
        print(
            f"{'load':<6} {'nodes':>5} {'spawn -> visible':>17} {'imports done -> visible':>24} "
            f"{'observer after: init -> all visible':>36} {'unseen':>6}"
        )
        for busy in (False, True):
            for count in sizes:
                results = {"spawn": [], "discovery": [], "after": [], "missed": []}
                with cpu_load(busy):
                    for _ in range(runs):
                        for key, values in run_case(count, env).items():
                            results[key] += values
                print(
                    f"{'busy' if busy else 'quiet':<6} {count:>5} {summary(results['spawn']):>17} "
                    f"{summary(results['discovery']):>24} {summary(results['after']):>36} "
                    f"{sum(results['missed']):>6}",
                    flush=True,
                )
        supervised_cases(sizes, runs, env, Path(tmp))
        count = max(sizes)
        print(f"PSS per node, {count} nodes running:")
        for label, profile in (("with the image segment", images), ("without", plain)):
            mib = pss_per_node(count, dict(env, FASTRTPS_DEFAULT_PROFILES_FILE=str(profile)))
            print(f"  {label:<24} {mib:7.1f} MiB ({profile.name})", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
