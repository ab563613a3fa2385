"""Whole-process time of `joshuac build` for the seed descriptions and synthetic 10/100/1000/3000-node ones.

    .venv/bin/python bench/compile.py [--quick]        # --quick: one seed and 10 nodes, one run each
"""

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
JOSHUAC = str(ROOT / ".venv" / "bin" / "joshuac")
RUNS = 7
SIZES = (10, 100, 1000, 3000)


def synthetic(nodes: int) -> str:
    """A valid description: encoders, mock actuators following them, cameras and a recorder."""
    lines = ['robot_config {', '  name: "synthetic"', "  mode: MODE_DATA_COLLECTION"]
    topics = []
    for i in range(nodes - 1):
        kind = i % 3
        if kind == 0:
            topics.append(f"/arm{i}/joint_states")
            lines.append(f'  node {{ name: "enc{i}" type: MOCK_ENCODER_PUBLISHER topic_name: "{topics[-1]}" }}')
        elif kind == 1:
            lines.append(f'  node {{ name: "act{i}" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "{topics[-1]}" '
                         f'state_topic: "/arm{i}/state" }}')
        else:
            lines.append(f'  node {{ name: "cam{i}" type: MOCK_CAMERA_PUBLISHER topic_name: "/cam{i}/image" }}')
    inputs = ", ".join(f'"{t}"' for t in topics[:50])
    lines.append(f'  node {{ name: "rec" type: DATA_SUBSCRIBER topic_name: "{topics[0]}" input_topics: [{inputs}] '
                 'output_directory: "/data/run" }')
    lines.append("}")
    return "\n".join(lines) + "\n"


def time_in_process(config: Path, runs: int) -> float:
    """Seconds of check + plan + render alone (no interpreter start, no file writes), best of `runs`."""
    from joshua_codegen.compile import compile_file

    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        compile_file(str(config))
        best = min(best, time.perf_counter() - start)
    return best


def time_build(config: Path, out: Path, runs: int) -> list[float]:
    samples = []
    for _ in range(runs):
        start = time.perf_counter()
        result = subprocess.run([JOSHUAC, "build", str(config), "-o", str(out)], capture_output=True, text=True)
        samples.append(time.perf_counter() - start)
        if result.returncode != 0:
            sys.exit(f"build of {config.name} failed:\n{result.stderr}")
    return samples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one seed and 10 nodes, one run each (for the tests)")
    args = parser.parse_args()
    runs, sizes, seeds = (1, (10,), 1) if args.quick else (RUNS, SIZES, None)
    print(f"joshuac build: whole process (median and min of {runs} runs), and compile alone in process (min)")
    print(f"{'description':32} {'nodes':>6} {'median s':>9} {'min s':>7} {'ms/node':>8} {'compile s':>10}")
    with tempfile.TemporaryDirectory() as tmp:
        cases = [(c, c.read_text().count("node {")) for c in sorted((ROOT / "config" / "robots").glob("*.pbtxt"))][:seeds]
        for size in sizes:
            path = Path(tmp) / f"synthetic_{size}.pbtxt"
            path.write_text(synthetic(size))
            cases.append((path, size))
        for config, count in cases:
            samples = time_build(config, Path(tmp) / "out" / config.stem, runs)
            median = statistics.median(samples)
            compile_s = time_in_process(config, runs)
            print(f"{config.name:32} {count:>6} {median:>9.3f} {min(samples):>7.3f} {1000 * median / count:>8.2f}"
                  f" {compile_s:>10.3f}")


if __name__ == "__main__":
    main()
