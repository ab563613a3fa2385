"""The three packages import one way: the runtime and the compiler read joshua_core, never each other.

A robot installs joshua_core and joshua_runtime only, so the runtime must not need the compiler or its
libraries (Jinja2, click); the core needs nothing but protobuf; the compiler runs where ROS is absent.
Inside the runtime, layers import downward only (tools, ai, sim, nodes, drivers): the contracts of
[tool.importlinter] in pyproject.toml, checked here by import-linter's lint-imports.
"""

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = {
    "joshua_core": ROOT / "core" / "joshua_core",
    "joshua_codegen": ROOT / "joshua_codegen",
    "joshua_runtime": ROOT / "runtime" / "joshua_runtime",
}
# What each package may not import, at any depth of its modules.
FORBIDDEN = {
    "joshua_core": {"joshua_codegen", "joshua_runtime", "jinja2", "click", "rclpy", "numpy"},
    "joshua_codegen": {"joshua_runtime", "rclpy", "numpy"},
    "joshua_runtime": {"joshua_codegen", "jinja2", "click"},
}


def imported_roots(path: Path) -> set[str]:
    """Top-level names of every module a source file imports (lazy imports inside functions too)."""
    roots = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            roots.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            roots.add(node.module.split(".")[0])
    return roots


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_package_imports_only_what_it_may(package):
    crossings = []
    for path in sorted(PACKAGES[package].rglob("*.py")):
        for root in sorted(imported_roots(path) & FORBIDDEN[package]):
            crossings.append(f"{path.relative_to(ROOT)} imports {root}")
    assert not crossings, "\n".join(crossings)


@pytest.mark.parametrize(
    "project, forbidden",
    [
        ("core/pyproject.toml", {"joshuac", "joshua-runtime", "jinja2", "click"}),
        ("runtime/pyproject.toml", {"joshuac", "jinja2", "click"}),
        ("pyproject.toml", {"joshua-runtime"}),
    ],
)
def test_distribution_does_not_depend_on_the_other_side(project, forbidden):
    metadata = tomllib.loads((ROOT / project).read_text())["project"]
    names = {
        requirement.split("[")[0].split(">")[0].split("=")[0].split("<")[0].strip().lower()
        for requirement in metadata["dependencies"]
    }
    assert not names & forbidden


@pytest.mark.process
def test_node_entrypoint_runs_without_the_compiler_installed():
    """Importing the runtime's entry, node base and a node class works with joshua_codegen, jinja2 and
    click made unimportable, as on a robot that installed only the runtime."""
    code = (
        "import sys\n"
        "for name in ('joshua_codegen', 'jinja2', 'click'):\n"
        "    sys.modules[name] = None\n"
        "from joshua_runtime.entrypoint import node_class\n"
        "node_class('ENCODER_PUBLISHER'); node_class('MOCK_ACTUATOR_SUBSCRIBER')\n"
        "import joshua_runtime.ai.staged_directory, joshua_runtime.emulators.cli\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr


@pytest.mark.process
def test_import_linter_contracts_are_kept():
    lint_imports = Path(sys.executable).with_name("lint-imports")
    result = subprocess.run(
        [str(lint_imports), "--no-cache", "--no-logo"], cwd=ROOT, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-2000:]
    assert "0 broken" in result.stdout


def test_every_runtime_module_has_its_layer():
    """A new subpackage of the runtime joins a layer, so that the contract also holds for it."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    (runtime,) = [c for c in config if c.get("containers") == ["joshua_runtime"]]
    layered = {name.strip() for layer in runtime["layers"] for name in layer.replace(":", "|").split("|")}
    package = PACKAGES["joshua_runtime"]
    modules = {p.stem for p in package.glob("*.py") if p.name != "__init__.py"}
    modules |= {p.name for p in package.iterdir() if p.is_dir() and any(p.glob("*.py"))}
    assert layered == modules
