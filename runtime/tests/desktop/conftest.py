"""Fixtures of the desktop panel tests: Qt offscreen and a screenshot folder (emulated buses: root conftest)."""

import os

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")  # before pytest-qt creates the QApplication

import pytest
from desktop_helpers import ARTIFACTS


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
