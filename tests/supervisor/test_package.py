"""The supervisor package: standard library only, one namespace when joined, and the joined code runs."""

import ast
import marshal
import os
import subprocess
import sys
import types
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


def generated_supervisor() -> dict[str, str]:
    """supervisor.py and supervisor_code.py, as joshuac writes them for the mock arm."""
    from google.protobuf import text_format

    from joshua_core.schema import RobotDescription

    config = ROOT / "config/robots/mock_arm.pbtxt"
    description = text_format.Parse(config.read_text(), RobotDescription())
    files = render(plan(description, config.name))
    return {path: files[path] for path in (emitter.SUPERVISOR_PATH, emitter.CODE_PATH)}


def write_supervisor(directory: Path) -> Path:
    for path, content in generated_supervisor().items():
        (directory / path).write_text(content)
    return directory / emitter.SUPERVISOR_PATH


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


def test_supervisor_py_holds_the_placeholder_robot_modules_names_and_the_code_file_every_other():
    from joshua_codegen.supervisor import robot

    files = generated_supervisor()
    text, code = files[emitter.SUPERVISOR_PATH], files[emitter.CODE_PATH]
    tree = ast.parse(text)
    joined = set()
    for name in package.MODULES:
        joined |= top_level_names(module_tree(name))
    assert top_level_names(ast.parse(code)) == joined
    data_names = top_level_names(tree) - {"supervisor_bytecode"}  # what compiles the code file or reads it cached
    assert data_names == top_level_names(module_tree(package.ROBOT_MODULE))
    assert not data_names & joined
    robot_literal = next(
        node.value
        for node in tree.body
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name) and node.targets[0].id == "ROBOT"
    )
    assert ast.literal_eval(robot_literal).keys() == robot.ROBOT.keys()
    assert "joshua_codegen" not in text and "joshua_codegen" not in code


@pytest.mark.process
def test_joined_code_runs_with_the_standard_library_alone(tmp_path):
    script = write_supervisor(tmp_path)
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


def run_help(script: Path, cache: Path, **env: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-S", str(script), "--help"],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
        env={"PATH": os.environ["PATH"], "XDG_CACHE_HOME": str(cache), **env},
        cwd=script.parent,
    )


def cached_code(cache: Path) -> list[Path]:
    return sorted((cache / emitter.BYTECODE_CACHE).glob("*.bytecode"))


@pytest.mark.process
def test_the_first_start_keeps_the_code_compiled_and_the_next_run_it_from_the_cache(tmp_path):
    script, cache = write_supervisor(tmp_path), tmp_path / "cache"
    first = run_help(script, cache)
    assert first.returncode == 0 and "--skip-preflight" in first.stdout, first.stderr
    [kept] = cached_code(cache)
    assert (kept.parent.stat().st_mode & 0o777, kept.parent.stat().st_uid) == (0o700, os.geteuid())
    assert isinstance(marshal.loads(kept.read_bytes()), types.CodeType)
    kept.write_bytes(marshal.dumps(compile("print('the cached code ran')", "other.py", "exec")))
    assert run_help(script, cache).stdout == "the cached code ran\n"


@pytest.mark.process
@pytest.mark.parametrize(
    "case", ["edited code file", "cache open to others", "PYTHONDONTWRITEBYTECODE", "no code in it", "relative home"]
)
def test_the_cache_is_not_used_for_other_code_or_when_others_may_write_it_and_not_written_when_asked(tmp_path, case):
    script, cache = write_supervisor(tmp_path), tmp_path / "cache"
    assert run_help(script, cache).returncode == 0
    [kept] = cached_code(cache)
    kept.write_bytes(marshal.dumps(compile("print('the cached code ran')", "other.py", "exec")))
    env = {}
    if case == "edited code file":
        code = tmp_path / emitter.CODE_PATH
        code.write_text(code.read_text().replace("Run the nodes of robot", "Run (edited) the nodes of robot"))
    elif case == "cache open to others":
        kept.parent.chmod(0o777)
    elif case == "no code in it":
        kept.write_bytes(marshal.dumps(["no", "code"]))
    elif case == "relative home":  # and XDG_CACHE_HOME relative too, which the XDG rules ignore
        env.update(HOME="home", XDG_CACHE_HOME="elsewhere")
    else:
        kept.unlink()
        env["PYTHONDONTWRITEBYTECODE"] = "1"
    result = run_help(script, cache, **env)
    assert result.returncode == 0, result.stderr
    assert "the cached code ran" not in result.stdout and "--skip-preflight" in result.stdout
    assert ("Run (edited) the nodes" in result.stdout) == (case == "edited code file")
    expected = {"edited code file": 2, "PYTHONDONTWRITEBYTECODE": 0}.get(case, 1)
    assert len(cached_code(cache)) == expected
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(["cache", *generated_supervisor()])
