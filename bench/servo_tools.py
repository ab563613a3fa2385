"""Bench tools on emulated STS3215 buses: scan time, status read rate, and the desktop panel's frame rate.

    .venv/bin/python bench/servo_tools.py [--repeats 5] [--read-s 3] [--gui-s 5] [--quick]

Scan: `joshua-servo scan`'s search (broadcast PING at each of the 8 baud rates, then one READ per
servo found) on a 6-servo bus with 1 Mbaud wire time emulated. Status: back-to-back `joshua-servo
status` reads (one SYNC_READ of 15 bytes from 6 servos). GUI: the joshua-desktop window offscreen,
fed 100 Hz telemetry of 6 joints from a worker thread through the same queued signal a real link
uses; it reports the frames drawn per second against its 30 fps frame timer (wall clock: it drops
when the machine is busy), and the GUI thread's CPU time for one frame (4 live plots with 10 s of
history, numbers and bars refreshed), timed by repainting back to back. --quick: one scan, half a
second of reads, 1 s of history and 1 s of frames.
"""

import argparse
import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from joshua_runtime.drivers.sts3215_status import read_status
from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from joshua_runtime.errors import DeviceError
from joshua_runtime.servo_tools.bus import open_bus
from joshua_runtime.servo_tools.scan import scan

IDS = [1, 2, 3, 4, 5, 6]
FEED_HZ = 100.0
HISTORY_S = 10.0
QUICK_HISTORY_S, QUICK_GUI_S, QUICK_READ_S = 1.0, 1.0, 0.5
REPAINTS = 50


def bench_scan(link: Path, repeats: int) -> float:
    times = []
    with open_bus(str(link)) as bus:
        for _ in range(repeats):
            start = time.perf_counter()
            found = scan(bus).servos
            times.append(time.perf_counter() - start)
            assert [servo.id for servo in found] == IDS, found
    return statistics.median(times)


def bench_status(link: Path, seconds: float) -> tuple[float, int]:
    """Successful reads per second, and how many reads failed (a starved emulator thread on a busy machine)."""
    reads = failures = 0
    with open_bus(str(link)) as bus:
        deadline = time.perf_counter() + seconds
        start = time.perf_counter()
        while time.perf_counter() < deadline:
            try:
                read_status(bus, IDS)
                reads += 1
            except DeviceError:
                failures += 1
        return reads / (time.perf_counter() - start), failures


def bench_gui(seconds: float, history_s: float = HISTORY_S) -> tuple[float, float]:
    from PySide6.QtCore import QTimer, Slot
    from PySide6.QtWidgets import QApplication

    from joshua_runtime.desktop.main_window import MainWindow
    from joshua_runtime.desktop.model import (
        JointSample,
        Presets,
        Telemetry,
        so100_limits,
    )
    from joshua_runtime.desktop.worker import LinkWorker
    from joshua_runtime.servo_tools.calibration_flow import ARMS

    arm = ARMS["so100"]

    class SyntheticFeed(LinkWorker):
        """Sinusoids at FEED_HZ, as a serial or ROS worker would emit them."""

        def connect_link(self) -> bool:
            self.connected.emit(f"synthetic feed, {FEED_HZ:g} Hz")
            return True

        def disconnect_link(self) -> None:
            pass

        def poll(self) -> None:
            now = time.monotonic()
            self.telemetry.emit(
                Telemetry(
                    now,
                    {
                        name: JointSample(
                            math.sin(now + i),
                            40 * math.sin(3 * now + i),
                            35 + i + math.sin(now / 3),
                            12.0 + 0.1 * math.sin(now + i),
                            True,
                        )
                        for i, name in enumerate(arm.joints)
                    },
                )
            )

        @Slot(object)
        def send_goals(self, goals) -> None:
            pass

        @Slot(bool)
        def set_torque(self, on) -> None:
            pass

        @Slot(str, bool)
        def set_joint_torque(self, joint, on) -> None:
            pass

        @Slot()
        def estop(self) -> None:
            pass

        @Slot(str, object)
        def calibrate(self, step, argument) -> None:
            pass

    app = QApplication.instance() or QApplication(sys.argv[:1])
    window = MainWindow(
        SyntheticFeed(FEED_HZ),
        list(arm.joints),
        so100_limits(),
        Presets(),
        arm,
        Path(tempfile.gettempdir()) / "unused.json",
    )
    window.show()
    window.start()
    marks = {}

    def mark(name: str) -> None:
        marks[name] = (time.monotonic(), sum(chart.frames_painted for chart in window.charts))

    def measure_frames() -> None:
        mark("end")
        for _ in range(REPAINTS):
            start = time.thread_time()  # CPU of this (the GUI) thread: other programs' load does not count
            window.frame()
            for chart in window.charts:
                chart.grab()  # paints the chart now, into a pixmap
            marks.setdefault("costs", []).append(time.thread_time() - start)
        app.quit()

    QTimer.singleShot(round(history_s * 1000), lambda: mark("start"))  # the plots hold 10 s of history
    QTimer.singleShot(round((history_s + seconds) * 1000), measure_frames)
    app.exec()
    (start_s, start_frames), (end_s, end_frames) = marks["start"], marks["end"]
    fps = (end_frames - start_frames) / len(window.charts) / (end_s - start_s)
    costs = marks["costs"]
    window.close()
    return fps, statistics.median(costs)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--read-s", type=float, default=3.0)
    parser.add_argument("--gui-s", type=float, default=5.0)
    parser.add_argument("--quick", action="store_true", help="a few seconds in all (for the tests)")
    args = parser.parse_args()
    history_s = HISTORY_S
    if args.quick:
        args.repeats, args.read_s, args.gui_s, history_s = 1, QUICK_READ_S, QUICK_GUI_S, QUICK_HISTORY_S
    with tempfile.TemporaryDirectory() as directory, Sts3215Emulator(Path(directory) / "ttyBENCH", IDS) as emulator:
        scan_s = bench_scan(emulator.link, args.repeats)
        print(f"scan of a 6-servo bus, 8 baud rates: median {scan_s * 1000:.0f} ms over {args.repeats} scans")
        rate, failures = bench_status(emulator.link, args.read_s)
        print(
            f"status of 6 servos (one SYNC_READ each): {rate:.0f} reads/s ({rate * len(IDS):.0f} servo readings/s), "
            f"{failures} failed"
        )
    fps, frame_s = bench_gui(args.gui_s, history_s)
    print(
        f"desktop panel, 100 Hz telemetry, 4 live plots: {fps:.1f} fps drawn (30 fps timer), "
        f"one frame {frame_s * 1000:.1f} ms of CPU (up to {1 / frame_s:.0f} fps on one free core)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
