"""Fixed and per-node cost of joshuac: build against a bare interpreter, check against `dora validate`.

    .venv/bin/python bench/compile.py [--quick]        # --quick: 10 nodes, one run each (for the tests)

Times are whole processes; "cpu" is user+system seconds of the child (what the machine spent, nearly
independent of other load), "wall" the elapsed time; each the minimum of the runs. `dora validate`
(dora-rs-cli, a Rust program) checks a dataflow YAML of the same nodes and edges as the description.
"""

import argparse
import resource
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


def timed(command: list[str], runs: int) -> tuple[float, float]:
    """(min cpu s, min wall s) of `command`, which must succeed."""
    cpu, wall = [], []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        result = subprocess.run(command, capture_output=True, text=True)
        wall.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
        if result.returncode != 0:
            sys.exit(f"{' '.join(command)} failed:\n{result.stderr}{result.stdout}")
    return min(cpu), min(wall)


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
            f"\nper node, min of {runs} runs   joshuac build cpu s   joshuac check cpu s   dora validate cpu s"
            "   check x dora"
        )
        for size in sizes:
            config, flow = tmp / f"synthetic_{size}.pbtxt", tmp / f"synthetic_{size}.yml"
            config.write_text(description(size))
            flow.write_text(dataflow(size, program))
            build = timed([JOSHUAC, "build", str(config), "-o", str(tmp / "out" / config.stem)], runs)[0]
            check = timed([JOSHUAC, "check", str(config)], runs)[0]
            dora = timed([DORA, "validate", str(flow)], runs)[0]
            print(f"{size:>5} nodes {build:>26.3f} {check:>21.3f} {dora:>21.3f} {check / max(dora, 1e-3):>14.1f}")


if __name__ == "__main__":
    main()
