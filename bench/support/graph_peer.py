"""The C++ peer of the discovery bench: cpp/bench/graph_node.cpp, a node on joshua_rcl with one JointState publisher."""

import subprocess

from support.described_nodes import ROOT

GRAPH_NODE = ROOT / "build" / "bench" / "graph_node"


def build() -> None:
    """`make -C cpp bench` (a no-op when up to date); SystemExit with its output when it fails."""
    made = subprocess.run(
        ["make", "--no-print-directory", "-s", "-C", str(ROOT / "cpp"), "bench"], capture_output=True, text=True
    )
    if made.returncode != 0:
        raise SystemExit(f"the C++ peer does not build (make -C cpp bench):\n{made.stdout}{made.stderr}")


def command(name: str, topic: str, rate_hz: float) -> list[str]:
    """The peer node named `name` publishing JointState on `topic` at `rate_hz`."""
    return [
        str(GRAPH_NODE),
        "--ros-args",
        "-r",
        f"__node:={name}",
        "-p",
        f"topic_name:={topic}",
        "-p",
        f"rate_hz:={rate_hz}",
    ]
