"""The node-type registry agrees with the schema, the runtime, the simulation and the planner."""

import ast
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

from joshua_codegen.check import check_text
from joshua_codegen.compile import node_settings
from joshua_codegen.plan import plan
from joshua_core.models import BUILTIN_MODELS
from joshua_core.node_families import Family
from joshua_core.node_types import NODE_TYPES, PROCESS_TYPES, SIMULATION_ENGINE, cpp_binaries
from joshua_core.schema import robot_config_pb2 as pb
from joshua_runtime.sim import model

NODE_FIELDS = set(pb.Node.DESCRIPTOR.fields_by_name)
ROOT = Path(__file__).resolve().parents[1]
# Values for every field some node type requires, so that a one-node description checks without errors.
REQUIRED_VALUES = {
    "serial_port": '"/dev/ttyUSB0"',
    "calibration_file": '"/c.json"',
    "model_path": '"/m"',
    "input_topics": '["/t"]',
    "output_directory": '"/d"',
    "executable": '"/bin/true"',
}


def defined_classes(target: str) -> tuple[str, set[str]]:
    """(class name, classes defined at top level of its module) for a `module:Class` target, read from
    the source without importing it (some node modules import torch)."""
    module_name, class_name = target.split(":")
    found = importlib.util.find_spec(module_name)
    assert found is not None and found.origin, f"module {module_name} does not exist"
    tree = ast.parse(Path(found.origin).read_text(encoding="utf-8"))
    return class_name, {node.name for node in tree.body if isinstance(node, ast.ClassDef)}


def test_every_schema_node_type_has_exactly_one_entry():
    declared = {name for name in pb.NodeType.keys() if name != "NODE_TYPE_UNSPECIFIED"}
    assert set(NODE_TYPES) == declared
    assert SIMULATION_ENGINE.name not in declared


@pytest.mark.parametrize("name", sorted(PROCESS_TYPES))
def test_entry_names_classes_that_exist(name):
    entry = PROCESS_TYPES[name]
    if entry.family == Family.CUSTOM:
        assert not entry.runtime_class  # runs its own executable
    else:
        class_name, classes = defined_classes(entry.runtime_class)
        assert class_name in classes, f"{entry.runtime_class} is not defined"
    if entry.hardware:
        class_name, classes = defined_classes(entry.sim_bridge)
        assert class_name in classes, f"{entry.sim_bridge} is not defined"
    else:
        assert not entry.sim_bridge


@pytest.mark.parametrize("name", sorted(NODE_TYPES))
def test_entry_fields_are_schema_fields(name):
    entry = NODE_TYPES[name]
    assert entry.fields <= NODE_FIELDS
    assert set(entry.required) <= NODE_FIELDS
    if entry.mock_of:
        assert NODE_TYPES[entry.mock_of].hardware and not entry.binary and not entry.hardware
    if entry.topic:
        assert entry.message_types, "a type with a topic_name needs its message types"


@pytest.mark.parametrize("name", sorted(n for n, e in NODE_TYPES.items() if e.cpp_parameters is not None))
def test_every_cpp_parameter_is_planned(name):
    """Planning a node with preferred_backend CPP passes every parameter its entry lists (no KeyError)."""
    text = (
        f'robot_config {{ name: "r" mode: MODE_TELEOPERATION node {{ name: "n" type: {name} '
        f'topic_name: "/t" serial_port: "/dev/ttyUSB0" calibration_file: "/c.json" preferred_backend: CPP }} }}'
    )
    settings = node_settings(text)
    assert settings["n"]["type"] == name


@pytest.mark.parametrize("name", sorted(NODE_TYPES))
def test_preferred_backend_cpp_runs_the_binary_or_is_reported_at_check_time(name):
    """A type with a C++ binary plans it; a type without one gets W102 and runs Python, never a crash."""
    entry = NODE_TYPES[name]
    fields = " ".join(f"{field}: {REQUIRED_VALUES[field]}" for field in entry.required)
    topic = 'topic_name: "/t"' if entry.topic else ""
    text = (
        f'robot_config {{ name: "r" mode: MODE_TELEOPERATION node {{ name: "n" type: {name} {topic} {fields} '
        "preferred_backend: CPP } }"
    )
    result = check_text("cpp.pbtxt", text)
    assert not result.has_errors, [d.message for d in result.diagnostics]
    warned = [d.message for d in result.diagnostics if d.code == "W102"]
    (process,) = [p for p in plan(result.description, "cpp.pbtxt").processes if p.name == "n"]
    if entry.binary:
        assert not warned and process.cpp_binary == entry.binary
    else:
        assert warned == [
            f"{name} has no C++ binary and always runs "
            f"{'its executable' if entry.declares_topics else 'its Python entrypoint'}; preferred_backend CPP is ignored"
        ]
        assert process.cpp_binary == "" and not process.cpp_args


@pytest.mark.process
def test_cpp_makefile_builds_exactly_the_binaries_of_the_registry():
    """cpp/Makefile reads the binaries from the registry, and each has its source with a main()."""
    made = subprocess.run(
        ["make", "-s", "--no-print-directory", "-C", str(ROOT / "cpp"), "binaries", f"PYTHON={sys.executable}"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert made.returncode == 0, made.stderr
    assert made.stdout.split() == cpp_binaries() != []
    with_main = {
        path.stem
        for path in (ROOT / "cpp" / "nodes").glob("*.cpp")
        if re.search(r"^int main\(", path.read_text(encoding="utf-8"), re.MULTILINE)
    }
    assert with_main == set(cpp_binaries())


def test_every_bridge_module_holds_the_one_bridge_the_registry_names():
    """sim/bridges/ has one module per simulated type, each defining one SimulationBridge subclass."""
    bridges_dir = ROOT / "runtime" / "joshua_runtime" / "sim" / "bridges"
    found = set()
    for path in sorted(bridges_dir.glob("*.py")):
        if path.name == "__init__.py":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        bridges = [
            node.name
            for node in tree.body
            if isinstance(node, ast.ClassDef) and any(getattr(b, "id", "") == "SimulationBridge" for b in node.bases)
        ]
        assert len(bridges) == 1, f"{path.name} defines {bridges}: one bridge a module"
        found.add(f"joshua_runtime.sim.bridges.{path.stem}:{bridges[0]}")
    assert found == {entry.sim_bridge for entry in NODE_TYPES.values() if entry.sim_bridge}


def test_checker_accepts_exactly_the_built_in_models_the_runtime_has():
    assert set(BUILTIN_MODELS) == set(model.BUILTIN_MODEL_FILES)
    for path in model.BUILTIN_MODEL_FILES.values():
        assert path.is_file(), path


def test_runtime_extras_are_extras_of_the_runtime_package():
    import tomllib

    declared = tomllib.loads((Path(__file__).resolve().parents[1] / "runtime" / "pyproject.toml").read_text())
    extras = set(declared["project"]["optional-dependencies"])
    assert {entry.runtime_extra for entry in PROCESS_TYPES.values()} - {""} <= extras
