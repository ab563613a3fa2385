"""action.yml (the composite action) and .github/workflows/ci.yml: checked by actionlint and shellcheck, and the
action's scripts run on this repository as a runner would run them (all but Python's set-up and pip)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

from testsupport.joshuac_cli import ROOT

pytestmark = pytest.mark.process  # actionlint, shellcheck and the action's scripts

BIN = ROOT / ".venv" / "bin"
WORKFLOW = ROOT / ".github" / "workflows" / "ci.yml"
ACTION = yaml.safe_load((ROOT / "action.yml").read_text())
SCRIPTS = {step["name"]: step for step in ACTION["runs"]["steps"] if "run" in step}
CHECKS = ("joshuac check", "joshuac fmt --check", "joshuac build --check")


def _actionlint(*args, cwd=ROOT) -> subprocess.CompletedProcess:
    env = {**os.environ, "PATH": f"{BIN}:{os.environ['PATH']}"}  # shellcheck too, for the workflow's run: scripts
    return subprocess.run(
        [BIN / "actionlint", "-no-color", *map(str, args)], cwd=cwd, env=env, capture_output=True, text=True
    )


def test_actionlint_passes_the_workflow_and_the_action_it_uses():
    result = _actionlint("-verbose", WORKFLOW)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'Rule "shellcheck" was disabled' not in result.stderr  # the run: scripts were checked
    assert f"Using project at {ROOT}" in result.stderr  # so action.yml was read for `uses: ./`


def test_actionlint_sees_a_wrong_use_of_the_action(tmp_path):
    """Not vacuous: a workflow giving the action an input it does not have is refused."""
    subprocess.run(["git", "init", "-q"], cwd=tmp_path, check=True)  # actionlint reads local actions of a repository
    shutil.copy(ROOT / "action.yml", tmp_path)
    (tmp_path / ".github" / "workflows").mkdir(parents=True)
    bad = WORKFLOW.read_text().replace("descriptions: config", "description: config")
    (tmp_path / ".github" / "workflows" / "ci.yml").write_text(bad)
    result = _actionlint(".github/workflows/ci.yml", cwd=tmp_path)
    assert result.returncode == 1 and 'input "description" is not defined' in result.stdout


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_the_action_scripts_pass_shellcheck(name):
    result = subprocess.run(
        [BIN / "shellcheck", "-s", "bash", "-"], input=SCRIPTS[name]["run"], capture_output=True, text=True
    )
    assert result.returncode == 0, result.stdout


def _run_checks(cwd: Path, inputs: dict[str, str], tmp_path: Path) -> tuple[list[int], str]:
    """Run the action's three checks in order, as the runner does: returns their exit codes and output."""
    env = {**os.environ, "PATH": f"{BIN}:{os.environ['PATH']}", "RUNNER_TEMP": str(tmp_path)}
    codes, output = [], ""
    for name in CHECKS:
        step = SCRIPTS[name]
        step_env = {
            key: value.replace("${{ inputs.descriptions }}", inputs.get("descriptions", "")).replace(
                "${{ inputs.builds }}", inputs.get("builds", "")
            )
            for key, value in step.get("env", {}).items()
        }
        result = subprocess.run(
            ["bash", "-e", "-o", "pipefail", "-c", step["run"]],
            cwd=cwd,
            env={**env, **step_env},
            capture_output=True,
            text=True,
        )
        codes.append(result.returncode)
        output += result.stdout + result.stderr
    return codes, output


BUILDS = "config/robots/*.pbtxt generated/{name}"


def test_the_checks_pass_on_this_repository(tmp_path):
    codes, output = _run_checks(ROOT, {"descriptions": "config/robots/*.pbtxt", "builds": BUILDS}, tmp_path)
    assert codes == [0, 0, 0], output
    assert "::warning file=config/robots/lego_bot.pbtxt" in output  # annotations


def test_the_checks_annotate_what_is_wrong(tmp_path):
    project = tmp_path / "project"
    shutil.copytree(ROOT / "config" / "robots", project / "config" / "robots")
    shutil.copytree(ROOT / "generated", project / "generated")
    arm = project / "config" / "robots" / "so100_arm.pbtxt"
    arm.write_text(arm.read_text().replace("camera_index: 0", "camera_index:   1"))
    codes, output = _run_checks(project, {"descriptions": "config/**/*.pbtxt", "builds": BUILDS}, tmp_path)
    assert codes == [0, 1, 1], output
    assert "::error file=config/robots/so100_arm.pbtxt,title=joshuac fmt::" in output
    assert (
        "::error file=config/robots/so100_arm.pbtxt,title=joshuac build --check::generated/so100_arm is not" in output
    )
    assert output.count("title=joshuac build --check") == 1  # the other robots are current
