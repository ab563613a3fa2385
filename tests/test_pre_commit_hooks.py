"""The hooks of .pre-commit-hooks.yaml, run by pre-commit in a temporary git repository as a user's repository would.

The hooks run as `language: system` (the joshuac of this environment, found on PATH, with no dependencies to
install), which a repository's configuration may choose; everything else (entry, arguments, which files, when) is the manifest's.
"""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from testsupport.joshuac_cli import ROOT

pytestmark = pytest.mark.process  # pre-commit

BIN = ROOT / ".venv" / "bin"
SEED = ROOT / "config" / "robots" / "so100_arm.pbtxt"
HOOKS = ("joshuac-check", "joshuac-fmt", "joshuac-build-check")
PRE_COMMIT_TIMEOUT_S = 120


def _git(*args, cwd: Path) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout.strip()


def _repository(path: Path) -> Path:
    path.mkdir()
    _git("init", "-q", "-b", "main", cwd=path)
    _git("config", "user.email", "hooks@example.com", cwd=path)
    _git("config", "user.name", "hooks", cwd=path)
    return path


def _commit(path: Path) -> str:
    _git("add", "-A", cwd=path)
    _git("commit", "-q", "-m", "state", cwd=path)
    return _git("rev-parse", "HEAD", cwd=path)


@pytest.fixture
def project(tmp_path):
    """A user's repository holding a description and its generated directory, with the hooks configured."""
    hooks = _repository(tmp_path / "hooks")
    shutil.copy(ROOT / ".pre-commit-hooks.yaml", hooks)
    rev = _commit(hooks)
    project = _repository(tmp_path / "project")
    shutil.copy(SEED, project / "robot.pbtxt")
    subprocess.run([BIN / "joshuac", "build", "robot.pbtxt", "-o", "generated/robot"], cwd=project, check=True)
    (project / ".pre-commit-config.yaml").write_text(_config(hooks, rev))
    _commit(project)
    return project


def _config(hooks: Path, rev: str, fmt_args: str = "") -> str:
    return f"""repos:
  - repo: {hooks}
    rev: {rev}
    hooks:
      - id: joshuac-check
        language: system
        additional_dependencies: []
      - id: joshuac-fmt
        language: system
        additional_dependencies: []{fmt_args}
      - id: joshuac-build-check
        language: system
        additional_dependencies: []
        args: [robot.pbtxt, -o, generated/robot]
"""


def _pre_commit(project: Path, tmp_path: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PATH": f"{BIN}:{os.environ['PATH']}", "PRE_COMMIT_HOME": str(tmp_path / "cache")}
    env.pop("VIRTUAL_ENV", None)
    return subprocess.run(
        [BIN / "pre-commit", "run", "--all-files", "--color", "never"],
        cwd=project,
        env=env,
        capture_output=True,
        text=True,
        timeout=PRE_COMMIT_TIMEOUT_S,
    )


def _verdicts(output: str) -> dict[str, str]:
    """Hook name -> Passed / Failed, from pre-commit's report."""
    verdicts = {}
    for line in output.splitlines():
        for hook in ("joshuac check", "joshuac fmt", "joshuac build --check"):
            if line.startswith(hook + "."):
                verdicts[hook] = line.rsplit(".", 1)[1].strip()
    return verdicts


def test_a_clean_repository_passes_every_hook(project, tmp_path):
    result = _pre_commit(project, tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert _verdicts(result.stdout) == {
        "joshuac check": "Passed",
        "joshuac fmt": "Passed",
        "joshuac build --check": "Passed",
    }


def test_an_error_fails_check_and_a_stale_build_fails_build_check(project, tmp_path):
    description = project / "robot.pbtxt"
    description.write_text(
        description.read_text().replace("qos_reliability: BEST_EFFORT", "qos_reliability: BEST_EFORT")
    )
    result = _pre_commit(project, tmp_path)
    assert result.returncode == 1
    assert _verdicts(result.stdout)["joshuac check"] == "Failed"
    assert "robot.pbtxt:" in result.stdout and "error[E004]" in result.stdout

    description.write_text(SEED.read_text().replace("camera_index: 0", "camera_index: 1"))
    result = _pre_commit(project, tmp_path)
    assert _verdicts(result.stdout) == {
        "joshuac check": "Passed",
        "joshuac fmt": "Passed",
        "joshuac build --check": "Failed",
    }
    assert "nodes/camera_publisher.py" in result.stdout


def test_fmt_checks_and_with_write_fixes(project, tmp_path):
    description = project / "robot.pbtxt"
    canonical = description.read_text()
    description.write_text(canonical.replace("\n  node {", "\n node {"))
    result = _pre_commit(project, tmp_path)
    assert _verdicts(result.stdout)["joshuac fmt"] == "Failed"
    assert "robot.pbtxt is not formatted" in result.stdout
    assert description.read_text() != canonical  # --check writes nothing

    config = project / ".pre-commit-config.yaml"
    hooks_rev = config.read_text().split("rev: ")[1].split("\n")[0]
    config.write_text(_config(project.parent / "hooks", hooks_rev, "\n        args: [--write]"))
    result = _pre_commit(project, tmp_path)
    assert _verdicts(result.stdout)["joshuac fmt"] == "Failed"  # pre-commit fails a hook that changed files
    assert description.read_text() == canonical
    assert _pre_commit(project, tmp_path).returncode == 0
