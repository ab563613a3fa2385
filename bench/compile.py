"""Fixed and per-node cost of joshuac: build against check of the same file, a bare interpreter and `dora validate`.

    .venv/bin/python bench/compile.py [--quick]        # --quick: 10 nodes, one run each (for the tests)

Times are whole processes; "cpu" is user+system seconds of the child (what the machine spent, nearly
independent of other load), "wall" the elapsed time; each the minimum of the runs, the commands of one
size taking turns run by run. "build" writes into the output of the previous build (the usual case: CI,
`make generate`, `run --watch`), "fresh" into a directory that does not exist yet; `cp -r` of that output
is the floor of a fresh build's file creation, measured alongside (on ext4 a new inode costs a search
past every inode freed in the last minutes, so it depends on what the machine deleted lately).
`dora validate` (dora-rs-cli, a Rust program) checks a dataflow YAML of the same nodes and edges.
"""

import argparse
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = ROOT / ".venv" / "bin"
JOSHUAC, PYTHON, DORA = str(BIN / "joshuac"), str(BIN / "python"), str(BIN / "dora")
RUNS = 7
SIZES = (10, 100, 1000, 3000)
RECORDED_INPUTS = 50  # topics the synthetic recorder reads
LINEAR_FROM = 100  # sizes from which the cost per added node is printed (below, the fixed cost dominates)


def synthetic_nodes(nodes: int) -> list[tuple[str, str, str, list[str]]]:
    """(name, kind, published topic, read topics) of encoders, actuators following them, cameras and a recorder."""
    found, encoders = [], []
    for i in range(nodes - 1):
        kind = ("encoder", "actuator", "camera")[i % 3]
        if kind == "encoder":
            encoders.append(f"/arm{i}/joint_states")
            found.append((f"enc{i}", kind, encoders[-1], []))
        elif kind == "actuator":
            found.append((f"act{i}", kind, f"/arm{i}/state", [encoders[-1]]))
        else:
            found.append((f"cam{i}", kind, f"/cam{i}/image", []))
    found.append(("rec", "recorder", "", encoders[:RECORDED_INPUTS]))
    return found


def description(nodes: int) -> str:
    """A valid joshuac description of the synthetic nodes."""
    lines = ["robot_config {", '  name: "synthetic"', "  mode: MODE_DATA_COLLECTION"]
    for name, kind, published, read in synthetic_nodes(nodes):
        if kind == "encoder":
            lines.append(f'  node {{ name: "{name}" type: MOCK_ENCODER_PUBLISHER topic_name: "{published}" }}')
        elif kind == "actuator":
            lines.append(
                f'  node {{ name: "{name}" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "{read[0]}" '
                f'state_topic: "{published}" }}'
            )
        elif kind == "camera":
            lines.append(f'  node {{ name: "{name}" type: MOCK_CAMERA_PUBLISHER topic_name: "{published}" }}')
        else:
            inputs = ", ".join(f'"{topic}"' for topic in read)
            lines.append(
                f'  node {{ name: "{name}" type: DATA_SUBSCRIBER topic_name: "{read[0]}" '
                f'input_topics: [{inputs}] output_directory: "/data/run" }}'
            )
    return "\n".join(lines + ["}"]) + "\n"


def dataflow(nodes: int, program: Path) -> str:
    """The same nodes and edges as a dora dataflow: each topic an output of its publisher, read as an input."""
    owner = {published: name for name, _kind, published, _read in synthetic_nodes(nodes) if published}
    lines = ["nodes:"]
    for name, _kind, published, read in synthetic_nodes(nodes):
        lines += [f"  - id: {name}", f"    path: {program}"]
        if published:
            lines += ["    outputs:", f"      - {published.strip('/').replace('/', '_')}"]
        if read:
            lines.append("    inputs:")
            lines += [
                f"      {topic.strip('/').replace('/', '_')}: {owner[topic]}/{topic.strip('/').replace('/', '_')}"
                for topic in read
            ]
    return "\n".join(lines) + "\n"


def cpu_of(command: list[str]) -> tuple[float, float]:
    """(cpu s, wall s) of one run of `command`, which must succeed."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{result.stderr}{result.stdout}")
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, wall


def timed(command: list[str], runs: int) -> tuple[float, float]:
    """(min cpu s, min wall s) of `command`, which must succeed."""
    cpu, wall = zip(*(cpu_of(command) for _ in range(runs)))
    return min(cpu), min(wall)


def per_size(size: int, runs: int, tmp: Path, program: Path) -> dict[str, float]:
    """Min cpu s of each command on the synthetic graph of `size` nodes, the commands taking turns."""
    config, flow = tmp / f"synthetic_{size}.pbtxt", tmp / f"synthetic_{size}.yml"
    config.write_text(description(size))
    flow.write_text(dataflow(size, program))
    out, fresh, copy = tmp / "out" / config.stem, tmp / "fresh" / config.stem, tmp / "copy" / config.stem
    cpu_of([JOSHUAC, "build", str(config), "-o", str(out)])  # the previous build the timed ones replace
    copy.parent.mkdir(exist_ok=True)
    commands = {
        "build": [JOSHUAC, "build", str(config), "-o", str(out)],
        "fresh": [JOSHUAC, "build", str(config), "-o", str(fresh)],
        "cp": ["cp", "-r", str(out), str(copy)],
        "check": [JOSHUAC, "check", str(config)],
        "dora": [DORA, "validate", str(flow)],
    }
    found = {name: [] for name in commands}
    for _ in range(runs):
        for name, command in commands.items():
            shutil.rmtree(fresh if name == "fresh" else copy, ignore_errors=True)
            found[name].append(cpu_of(command)[0])
    return {name: min(values) for name, values in found.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10 nodes, one run each (for the tests)")
    args = parser.parse_args()
    runs, sizes = (1, (10,)) if args.quick else (RUNS, SIZES)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        program = tmp / "node.py"
        program.write_text("")
        bare = timed([PYTHON, "-c", "pass"], runs)
        print(f"fixed cost, min of {runs} runs        cpu s   wall s   cpu x bare python")
        print(f"{'python -c pass':32} {bare[0]:>8.3f} {bare[1]:>8.3f} {1:>8.1f}")
        for config in sorted((ROOT / "config" / "robots").glob("*.pbtxt"))[: 1 if args.quick else None]:
            cpu, wall = timed([JOSHUAC, "build", str(config), "-o", str(tmp / "out" / config.stem)], runs)
            print(f"{'joshuac build ' + config.name:32} {cpu:>8.3f} {wall:>8.3f} {cpu / bare[0]:>8.1f}")
        print(
            f"\nper size, cpu s, min of {runs} runs   build   fresh  cp -r   check    dora"
            "   build x check   fresh x check   check x dora"
        )
        found = {}
        for size in sizes:
            cpu = found[size] = per_size(size, runs, tmp, program)
            print(
                f"{size:>5} nodes {cpu['build']:>24.3f} {cpu['fresh']:>7.3f} {cpu['cp']:>6.3f} {cpu['check']:>7.3f}"
                f" {cpu['dora']:>7.3f} {cpu['build'] / cpu['check']:>15.2f} {cpu['fresh'] / cpu['check']:>15.2f}"
                f" {cpu['check'] / max(cpu['dora'], 1e-3):>14.1f}"
            )
        for small, large in zip(sizes, sizes[1:]):
            if small >= LINEAR_FROM:
                step = {
                    name: (found[large][name] - found[small][name]) / (large - small) * 1000
                    for name in ("build", "check")
                }
                print(
                    f"{small} -> {large} nodes, cpu ms per node: build {step['build']:.3f}, check {step['check']:.3f}"
                )


if __name__ == "__main__":
    main()
