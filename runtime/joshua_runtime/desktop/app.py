"""`joshua-desktop`: drive, watch and calibrate an arm, straight on its servo bus or over ROS.

    joshua-desktop --port /dev/ttyACM0 [--calibration follower.json]
    joshua-desktop --ros --state-topic /follower/joint_states --command-topic /follower/command
    joshua-desktop --emulate --demo --screenshot panel.png --quit-after 4     (no hardware)

--screenshot renders offscreen when there is no display, saves the window after --quit-after
seconds and exits: 0, or 3 when the link never came up.
"""

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

from joshua_runtime.errors import JoshuaError

EXIT_NO_DISPLAY = 2
EXIT_LINK_FAILED = 3
DEFAULT_SCREENSHOT_DELAY_S = 2.0
DEMO_PRESET_PERIOD_S = 1.5


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="joshua-desktop",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__,
    )
    link = parser.add_mutually_exclusive_group(required=True)
    link.add_argument("--port", help="serial port of the servo bus")
    link.add_argument("--ros", action="store_true", help="connect to a running robot over ROS 2")
    link.add_argument("--emulate", action="store_true", help="an emulated SO-100 bus, for trying the panel")
    parser.add_argument("--baud", type=int, default=1_000_000)
    parser.add_argument("--ids", default="1,2,3,4,5,6", help="servo ids in joint order")
    parser.add_argument("--calibration", help="LeRobot calibration file of the arm on --port")
    parser.add_argument("--robot", default="so100", choices=("so100", "so101"))
    parser.add_argument("--state-topic", default="/follower/joint_states")
    parser.add_argument("--command-topic", default="/follower/command")
    parser.add_argument("--presets", help='JSON file of extra presets: {"name": {"joint": rad}}')
    parser.add_argument("--calibration-output", type=Path, default=Path("so100_follower.json"))
    parser.add_argument("--demo", action="store_true", help="with --emulate: cycle through the presets")
    parser.add_argument("--screenshot", type=Path, help="save the window to this PNG and exit")
    parser.add_argument("--quit-after", type=float, metavar="S", help="exit after S seconds")
    return parser


def _ids(text: str) -> list[int]:
    try:
        return [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise JoshuaError(f"--ids: expected comma-separated servo ids, got {text!r}") from None


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    has_display = any(os.environ.get(name) for name in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"))
    if not has_display:
        if not args.screenshot:
            print(
                "joshua-desktop: error: no display (set DISPLAY, or render offscreen with --screenshot PATH)",
                file=sys.stderr,
            )
            return EXIT_NO_DISPLAY
        os.environ["QT_QPA_PLATFORM"] = "offscreen"
    try:
        return _run(args)
    except JoshuaError as exc:
        print(f"joshua-desktop: error: {exc}", file=sys.stderr)
        return exc.exit_code


def _run(args) -> int:
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication

    from joshua_runtime.desktop.main_window import MainWindow
    from joshua_runtime.desktop.model import load_presets, so100_limits
    from joshua_runtime.servo_tools.calibration_flow import ARMS

    arm = ARMS[args.robot]
    joints, ids = list(arm.joints), _ids(args.ids)
    presets = load_presets(args.presets, joints)
    emulator = _start_emulator(ids) if args.emulate else None
    app = QApplication.instance() or QApplication(sys.argv[:1])
    worker = _worker(args, joints, ids, emulator)
    window = MainWindow(worker, joints, so100_limits(), presets, arm, args.calibration_output)
    window.show()
    window.start()
    if emulator is not None and args.demo:
        _demo(window, presets)
    delay = (
        args.quit_after if args.quit_after is not None else (DEFAULT_SCREENSHOT_DELAY_S if args.screenshot else None)
    )
    if delay is not None:

        def finish():
            if args.screenshot:
                args.screenshot.parent.mkdir(parents=True, exist_ok=True)
                window.grab().save(str(args.screenshot))
            window.close()
            app.quit()

        QTimer.singleShot(round(delay * 1000), finish)
    try:
        app.exec()
    finally:
        window.thread.stop()
        if emulator is not None:
            emulator.stop()
            shutil.rmtree(emulator.link.parent, ignore_errors=True)  # _start_emulator's directory
    return EXIT_LINK_FAILED if window.link_failed else 0


def _worker(args, joints, ids, emulator):
    if args.ros:
        from joshua_runtime.desktop.ros_worker import RosWorker

        return RosWorker(args.state_topic, args.command_topic)
    from joshua_runtime.desktop.serial_worker import SerialWorker

    port = str(emulator.link) if emulator is not None else args.port
    return SerialWorker(port, joints, ids, args.baud, args.calibration, arm=args.robot)


def _start_emulator(ids):
    """An SO-100 bus on a pty, with a little spread in temperature and voltage between servos."""
    from joshua_runtime.emulators.sts3215 import Sts3215Emulator

    emulator = Sts3215Emulator(Path(tempfile.mkdtemp(prefix="joshua-desktop-")) / "ttyEMULATED", ids).start()
    for index, servo_id in enumerate(ids):
        emulator.set_sensor(servo_id, "Present_Temperature", 31 + 2 * index)
        emulator.set_sensor(servo_id, "Present_Voltage", 122 - index)
    return emulator


def _demo(window, presets) -> None:
    """Torque on, then a new preset every DEMO_PRESET_PERIOD_S, so the plots move."""
    from PySide6.QtCore import QTimer

    names = [name for name in presets.names() if name != "grip_open"] + ["grip_open"]
    state = {"next": 0}

    def step():
        if state["next"] == 0:
            window.torque_requested.emit(True)
        window.apply_preset(names[state["next"] % len(names)])
        state["next"] += 1

    timer = QTimer(window)
    timer.setInterval(round(DEMO_PRESET_PERIOD_S * 1000))
    timer.timeout.connect(step)
    timer.start()
    QTimer.singleShot(300, step)


if __name__ == "__main__":
    sys.exit(main())
