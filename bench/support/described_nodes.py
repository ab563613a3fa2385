"""Start benchmark nodes as generated entrypoints do, with settings joshuac compiles from a description text."""

from collections.abc import Sequence
from pathlib import Path

from joshua_codegen.compile import DescriptionError, cpp_commands, node_settings

ROOT = Path(__file__).resolve().parents[2]
PYTHON = str(ROOT / ".venv" / "bin" / "python")
CPP_BIN_DIR = ROOT / "build" / "bin"  # where `make cpp` puts the C++ node binaries


def compiled_settings(
    description_text: str, overrides: Sequence[str] = (), path: str = "bench.pbtxt"
) -> dict[str, dict]:
    """Every process's settings by name (the simulation engine's under "simulation"), as `joshuac build` writes them.

    `overrides` are `--set` values (`NODE.serial_port=/tmp/x/ttyLEADER`), which need no quoting, so
    runtime paths go there. A description with errors ends the benchmark with joshuac's diagnostics.
    """
    try:
        return node_settings(description_text, overrides, path)
    except DescriptionError as exc:
        raise SystemExit(f"the benchmark's description has errors:\n{exc}") from None


def compiled_cpp_commands(
    description_text: str, overrides: Sequence[str] = (), path: str = "bench.pbtxt"
) -> dict[str, list[str]]:
    """The argv the supervisor execs for each node with a C++ binary in build/bin, by name."""
    try:
        return cpp_commands(description_text, str(CPP_BIN_DIR), overrides, path)
    except DescriptionError as exc:
        raise SystemExit(f"the benchmark's description has errors:\n{exc}") from None


def node_command(settings: dict) -> list[str]:
    """The command that runs one node process, calling `run_node` as a generated entrypoint does."""
    code = f"import sys\nfrom joshua_runtime.entrypoint import run_node\nsys.exit(run_node({settings!r}))"
    return [PYTHON, "-c", code]


def write_fastdds_profiles(
    description_text: str, directory: Path, overrides: Sequence[str] = (), path: str = "bench.pbtxt"
) -> dict[str, Path]:
    """Write the Fast DDS profiles `joshuac build` writes for a description into `directory`;
    return the one each process loads (its FASTRTPS_DEFAULT_PROFILES_FILE), by process name."""
    from joshua_codegen.compile import plan_text
    from joshua_codegen.emitters import fastdds
    from joshua_codegen.render import render

    try:
        robot = plan_text(description_text, overrides, path)
    except DescriptionError as exc:
        raise SystemExit(f"the benchmark's description has errors:\n{exc}") from None
    files = render(robot)
    for name in fastdds.PROFILE_PATHS:
        (directory / name).write_text(files[name])
    return {process.name: directory / fastdds.profile_path(process) for process in robot.processes}


def topic_qos(topic: dict):
    """The rclpy QoSProfile of a topic of compiled settings (`{"name", "message_type", "qos"}`)."""
    from joshua_core.settings import QosSettings
    from joshua_runtime.qos import qos_profile

    return qos_profile(QosSettings(**topic["qos"]))
