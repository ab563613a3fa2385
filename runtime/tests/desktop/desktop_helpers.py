"""Helpers of the desktop tests: build a panel on a worker, as joshua-desktop does; where screenshots go."""

from pathlib import Path

from joshua_runtime.desktop.main_window import MainWindow
from joshua_runtime.desktop.model import Presets, so100_limits
from joshua_runtime.servo_tools.calibration_flow import ARMS

SO100 = ARMS["so100"]
JOINTS = list(SO100.joints)
IDS = list(SO100.ids)
LINK_TIMEOUT_MS = 10_000
# Screenshots are kept for review here (gitignored), and their paths printed.
ARTIFACTS = Path(__file__).resolve().parents[3] / "artifacts" / "desktop"


def open_panel(
    qtbot,
    worker,
    calibration_output: Path | None = None,
    presets: Presets | None = None,
    timeout_ms: int = LINK_TIMEOUT_MS,
) -> MainWindow:
    window = MainWindow(
        worker, JOINTS, so100_limits(), presets or Presets(), SO100, calibration_output or Path("unused.json")
    )
    qtbot.addWidget(window)
    window.show()
    window.start()
    qtbot.waitUntil(lambda: window.latest is not None, timeout=timeout_ms)
    return window


def close_panel(window: MainWindow) -> None:
    window.close()
