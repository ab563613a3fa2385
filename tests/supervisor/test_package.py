"""The supervisor package: standard library only, one namespace when joined, and the joined file runs."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from joshua_codegen import supervisor as package
from joshua_codegen.emitters import supervisor as emitter
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from testsupport.joshuac_cli import ROOT

PACKAGE_DIR = Path(package.__file__).parent


def module_tree(name: str) -> ast.Module:
    return ast.parse((PACKAGE_DIR / f"{name}.py").read_text())


def top_level_names(tree: ast.Module) -> set[str]:
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                names.update(n.id for n in ast.walk(target) if isinstance(n, ast.Name))
    return names


def generated_supervisor() -> str:
    from google.protobuf import text_format

    from joshua_core.schema import RobotDescription

    config = ROOT / "config/robots/mock_arm.pbtxt"
    description = text_format.Parse(config.read_text(), RobotDescription())
    return render(plan(description, config.name))[emitter.SUPERVISOR_PATH]


def test_every_module_is_joined_once_and_robot_is_left_to_the_emitter():
    files = {path.stem for path in PACKAGE_DIR.glob("*.py")} - {"__init__"}
    assert sorted(package.MODULES) == sorted(files - {package.ROBOT_MODULE})
    assert len(set(package.MODULES)) == len(package.MODULES)


def test_modules_import_only_the_standard_library_and_each_other():
    for name in [*package.MODULES, package.ROBOT_MODULE]:
        for node in ast.walk(module_tree(name)):
            if isinstance(node, ast.Import):
                modules = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                modules = [node.module or ""]
                if modules[0].startswith(emitter.PACKAGE_PREFIX):
                    assert node.col_offset == 0, f"{name}: package imports must be at the top level"
                    assert modules[0].removeprefix(emitter.PACKAGE_PREFIX) in [*package.MODULES, package.ROBOT_MODULE]
                    continue
            else:
                continue
            for module in modules:
                assert module.split(".")[0] in sys.stdlib_module_names, f"{name} imports {module}"


def test_top_level_names_are_unique_across_modules():
    seen: dict[str, str] = {}
    for name in [*package.MODULES, package.ROBOT_MODULE]:
        for defined in top_level_names(module_tree(name)):
            assert defined not in seen, f"{defined} is defined in {seen[defined]} and {name}"
            seen[defined] = name


def test_generated_file_defines_exactly_the_names_of_the_placeholder_robot_module():
    from joshua_codegen.supervisor import robot

    text = generated_supervisor()
    tree = ast.parse(text)
    joined = set()
    for name in package.MODULES:
        joined |= top_level_names(module_tree(name))
    data_names = top_level_names(tree) - joined
    assert data_names == top_level_names(module_tree(package.ROBOT_MODULE))
    robot_literal = next(
        node.value
        for node in tree.body
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name) and node.targets[0].id == "ROBOT"
    )
    assert ast.literal_eval(robot_literal).keys() == robot.ROBOT.keys()
    assert "joshua_codegen" not in text


@pytest.mark.process
def test_joined_file_runs_with_the_standard_library_alone(tmp_path):
    script = tmp_path / "supervisor.py"
    script.write_text(generated_supervisor())
    result = subprocess.run(
        [sys.executable, "-I", "-S", str(script), "--help"], capture_output=True, text=True, timeout=30, check=False
    )
    assert result.returncode == 0, result.stderr
    assert "--skip-preflight" in result.stdout
    bad = subprocess.run(
        [sys.executable, "-I", "-S", str(script), "--duration", "-1"],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    assert bad.returncode == 2 and "positive number of seconds" in bad.stderr


def test_placeholder_robot_writes_the_settings_format_the_compiler_writes():
    """The package's own tests run on robot.py's placeholder data; it must name today's format."""
    from joshua_codegen.supervisor.robot import ROBOT
    from joshua_core.settings import FORMAT_VERSION

    assert ROBOT["settings_format_version"] == FORMAT_VERSION
