"""`joshua-desktop` as a command: offscreen screenshots, a link that fails, bad preset files."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from desktop_helpers import ARTIFACTS
from PySide6.QtGui import QImage

from joshua_runtime.desktop.model import load_presets
from joshua_runtime.errors import SettingsError

JOINTS = ["shoulder_pan", "gripper"]


def desktop(*argv, env=None):
    command = [Path(sys.executable).parent / "joshua-desktop", *map(str, argv)]  # the console script
    return subprocess.run(command, capture_output=True, text=True, timeout=60, check=False, env=env)


@pytest.mark.process
def test_screenshot_of_the_emulated_demo(tmp_path):
    presets = tmp_path / "presets.json"
    presets.write_text(json.dumps({"wave": {"shoulder_pan": 0.8, "wrist_roll": -1.0}}))
    path = ARTIFACTS / "demo.png"
    temporary = tmp_path / "tmp"  # where the emulated bus's pty link is made
    temporary.mkdir()
    result = desktop(
        "--emulate", "--demo", "--presets", presets, "--screenshot", path, "--quit-after", 4,
        env={**os.environ, "TMPDIR": str(temporary)},
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert list(temporary.iterdir()) == []
    image = QImage(str(path))
    assert (image.width(), image.height()) >= (1200, 700)
    print(f"screenshot: {path}")


@pytest.mark.process
def test_a_port_that_is_not_there_exits_3_after_the_screenshot(tmp_path):
    path = tmp_path / "missing.png"
    result = desktop("--port", tmp_path / "ttyNONE", "--screenshot", path, "--quit-after", 1)
    assert result.returncode == 3 and path.exists()


@pytest.mark.process
def test_no_display_is_one_line(tmp_path, monkeypatch):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"):
        monkeypatch.delenv(name, raising=False)
    result = desktop("--emulate")
    assert result.returncode == 2
    assert (
        result.stderr == "joshua-desktop: error: no display (set DISPLAY, or render offscreen with --screenshot PATH)\n"
    )


@pytest.mark.process
def test_bad_preset_file_is_one_line(tmp_path):
    presets = tmp_path / "presets.json"
    presets.write_text(json.dumps({"reach": {"elbow": 1.0}}))
    result = desktop("--emulate", "--presets", presets, "--screenshot", tmp_path / "x.png")
    assert result.returncode == 2
    assert (
        result.stderr == f"joshua-desktop: error: preset file {presets}: preset 'reach' names unknown joint 'elbow'\n"
    )


@pytest.mark.parametrize(
    ("document", "message"),
    [
        ("[]", "expected an object of preset names"),
        ('{"open": {}}', "preset 'open' must map joint names to radians"),
        ('{"open": {"gripper": "wide"}}', "preset 'open': gripper must be a number of radians"),
        ("{oops", "is unreadable"),
    ],
)
def test_preset_file_errors(tmp_path, document, message):
    path = tmp_path / "presets.json"
    path.write_text(document)
    with pytest.raises(SettingsError, match=message):
        load_presets(path, JOINTS)


def test_user_presets_join_the_builtin_ones(tmp_path):
    path = tmp_path / "presets.json"
    path.write_text(json.dumps({"open_wide": {"gripper": 1.7}}))
    presets = load_presets(path, JOINTS)
    assert presets.names() == ["home", "rest", "grip_open", "open_wide"]
    goals = presets.goals("open_wide", JOINTS)
    assert goals[1] == 1.7 and goals[0] != goals[0]  # NaN: the preset leaves shoulder_pan alone
