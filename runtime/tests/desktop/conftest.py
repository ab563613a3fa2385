"""Fixtures of the desktop panel tests: Qt offscreen, emulated buses on ptys, a screenshot folder."""

import os

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")  # before pytest-qt creates the QApplication

import pytest
from desktop_helpers import ARTIFACTS

from joshua_runtime.emulators.sts3215 import Sts3215Emulator


@pytest.fixture
def emulators(tmp_path):
    """Factory: emulators(name, ids=...) -> a started Sts3215Emulator at tmp_path/name."""
    started = []

    def make(name: str = "ttyBUS", ids=(1, 2, 3, 4, 5, 6), **options) -> Sts3215Emulator:
        emulator = Sts3215Emulator(tmp_path / name, ids, **options).start()
        started.append(emulator)
        return emulator

    yield make
    for emulator in started:
        emulator.stop()


@pytest.fixture
def screenshot():
    """screenshot(window, name) -> the PNG path it saved under artifacts/desktop/."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)

    def save(window, name: str):
        path = ARTIFACTS / f"{name}.png"
        assert window.grab().save(str(path))
        print(f"screenshot: {path}")
        return path

    return save
