"""joshuac installs on every supported Python found on the machine and gives byte-identical results on each.

The reference is the development environment's interpreter (the runtime's 3.11). Each interpreter found
(`testsupport/interpreters.py`: versioned names on PATH, pyenv's versions) gets a fresh environment with
joshuac and joshua-core installed from this checkout; it must check the seed descriptions and every
rule fixture, and build the seeds, exactly as the reference does.
"""

import filecmp
import os
import subprocess
from pathlib import Path

import pytest

from testsupport.interpreters import install_joshuac, supported_interpreters, with_shared_bytecode
from testsupport.joshuac_cli import CONFIGS, ROOT

INTERPRETERS = supported_interpreters()
RULE_FIXTURES = sorted(p for p in (ROOT / "tests" / "rules").glob("*/bad.pbtxt") if p.is_file())


def _relative(paths) -> list[str]:
    return [str(Path(p).relative_to(ROOT)) for p in paths]


def _outputs(run) -> dict[str, tuple[int, str, str]]:
    """What `run(*args)` answers to the checks both sides make, by name."""
    answers = {}
    for name, args in {
        "check seeds": ("check", *_relative(CONFIGS)),
        "check rule fixtures": ("check", *_relative(RULE_FIXTURES)),
        "check rule fixtures as json": ("check", "--format", "json", *_relative(RULE_FIXTURES)),
        "fmt --check seeds": ("fmt", "--check", *_relative(CONFIGS)),
        "explain": ("explain",),
    }.items():
        result = run(*args)
        answers[name] = (result.returncode, result.stdout, result.stderr)
    return answers


def _same_tree(left: Path, right: Path) -> list[str]:
    """Relative paths that differ between two directories (missing on one side included)."""
    comparison = filecmp.dircmp(left, right)
    differing = comparison.left_only + comparison.right_only + comparison.diff_files
    _, mismatch, errors = filecmp.cmpfiles(left, right, comparison.common_files, shallow=False)
    differing += mismatch + errors
    for name in comparison.common_dirs:
        differing += [f"{name}/{p}" for p in _same_tree(left / name, right / name)]
    return sorted(set(differing))


def test_every_supported_version_is_looked_for():
    """The machine's own 3.11 is always found, so the parametrized test below never runs empty."""
    assert "3.11" in INTERPRETERS, INTERPRETERS


def _command(bin_dir: Path, env: dict | None = None):
    def run(*args):
        command = [str(bin_dir / "joshuac"), *map(str, args)]
        return subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True)

    return run


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("reference")
    run = _command(ROOT / ".venv" / "bin")
    for config in CONFIGS:
        assert run("build", config, "-o", out / config.stem).returncode == 0
    return out, _outputs(run)


@pytest.mark.process
@pytest.mark.parametrize("version", sorted(INTERPRETERS))
def test_joshuac_on_each_python_matches_the_reference(version, reference, tmp_path):
    reference_builds, reference_answers = reference
    bin_dir = install_joshuac(INTERPRETERS[version], tmp_path / "venv")
    run = _command(bin_dir, with_shared_bytecode(dict(os.environ), bin_dir.parent / "bytecode"))
    answers = _outputs(run)
    for name, expected in reference_answers.items():
        assert answers[name] == expected, f"Python {version}: `{name}` answers differently"
    for config in CONFIGS:
        out = tmp_path / "out" / config.stem
        result = run("build", config, "-o", out)
        assert result.returncode == 0, result.stderr
        assert _same_tree(out, reference_builds / config.stem) == [], f"Python {version}: {config.name}"
