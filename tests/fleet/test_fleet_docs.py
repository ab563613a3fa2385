"""docs/fleet.md as a user reads it: its fleet file checks and builds, signed, and the options it names exist."""

import re
import shutil
import subprocess
import sys
from pathlib import Path

from testsupport.joshuac_cli import ROOT, joshuac

DOCS = ROOT / "docs" / "fleet.md"
FLEET_BLOCK = re.compile(r"^<!-- test: fleet-file -->\n```\n(.*?)^```$", re.MULTILINE | re.DOTALL)
JOSHUA_FLEET = Path(sys.executable).with_name("joshua-fleet")


def test_the_fleet_file_of_the_docs_checks_and_builds_signed(tmp_path):
    (block,) = FLEET_BLOCK.findall(DOCS.read_text())
    (tmp_path / "config" / "robots").mkdir(parents=True)
    shutil.copy(ROOT / "config" / "robots" / "so100_arm.pbtxt", tmp_path / "config" / "robots")
    (tmp_path / "fleet").mkdir()
    (tmp_path / "fleet" / "lab.pbtxt").write_text(block)
    checked = joshuac("check", "fleet/lab.pbtxt", cwd=tmp_path)
    assert checked.returncode == 0, checked.stdout
    assert checked.stdout in DOCS.read_text()  # the docs show what check prints, as it prints it
    assert joshuac("fmt", "--check", "fleet/lab.pbtxt", cwd=tmp_path).returncode == 0
    assert joshuac("keygen", "release.key", cwd=tmp_path).returncode == 0
    built = joshuac("build", "fleet/lab.pbtxt", "-o", "out/lab", "--sign", "release.key", cwd=tmp_path)
    assert built.returncode == 0, built.stderr
    assert re.search(r"^joshuac: arm_2: release [0-9a-f]{12} signed in out/lab/robots/arm_2$", built.stderr, re.M)
    manifest = (tmp_path / "out/lab/robots/arm_2/manifest.json").read_text()
    assert "/dev/ttyACM1" in manifest and "/dev/ttyACM0" not in manifest


def test_the_options_the_docs_name_exist():
    text = DOCS.read_text()
    deploy = subprocess.run([str(JOSHUA_FLEET), "deploy", "--help"], capture_output=True, text=True).stdout
    rollback = subprocess.run([str(JOSHUA_FLEET), "rollback", "--help"], capture_output=True, text=True).stdout
    for option in re.findall(r"`(--(?:canary|batch|limit|on-failure|health-timeout))\b", text):
        assert option in deploy, option
    assert (
        "--out" in rollback
        and "--rollout-state" in subprocess.run([str(JOSHUA_FLEET), "--help"], capture_output=True, text=True).stdout
    )
