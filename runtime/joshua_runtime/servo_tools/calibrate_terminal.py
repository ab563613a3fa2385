"""`joshua-servo calibrate`: the guided calibration in a terminal, Enter to advance, live MIN/POS/MAX.

Each joint is checked as soon as it is done; the joints that pass are saved even when another fails."""

import select
import sys
import time
from pathlib import Path

from joshua_runtime.drivers.calibration import save_calibration
from joshua_runtime.servo_tools.calibration_flow import CalibrationError, CalibrationFlow

SAMPLE_PERIOD_S = 0.05


def enter_pressed(stream=sys.stdin) -> bool:
    """True (and the line consumed) once the user has pressed Enter; never blocks."""
    ready, _, _ = select.select([stream], [], [], 0)
    if not ready:
        return False
    stream.readline()
    return True


def wait_for_enter(stream=sys.stdin) -> None:
    stream.readline()


def calibrate(
    bus,
    arm,
    output: Path,
    joints: tuple[str, ...] | None = None,
    kept: dict | None = None,
    out=sys.stdout,
    stdin=sys.stdin,
) -> dict[str, str]:
    """Run the flow over `joints` (default all), checking each joint as soon as it is swept, then write
    `output` with the joints that passed, after the `kept` entries of the others (from an earlier run).

    A joint that fails its check is named at once and the next joint follows; returns why each failed.
    """
    joints = joints or arm.joints
    flow = CalibrationFlow(bus, arm)
    flow.start(joints)
    passed, failed = {}, {}
    for joint in joints:
        print(f"{arm.homing_instruction(joint)} Press Enter.", file=out, flush=True)
        wait_for_enter(stdin)
        flow.home(joint)
        if joint in arm.continuous_joints:
            print(arm.sweep_instruction(joint), file=out, flush=True)
        else:
            print(f"{arm.sweep_instruction(joint)} Press Enter when done.", file=out, flush=True)
            while not enter_pressed(stdin):
                reading = flow.sample(joint)
                if out.isatty():
                    print(
                        f"\r  MIN {reading.low:5d}  POS {reading.position:5d}  MAX {reading.high:5d}", end="", file=out
                    )
                time.sleep(SAMPLE_PERIOD_S)
            reading = flow.sample(joint)
        try:
            passed[joint] = flow.calibration_of(joint)
        except CalibrationError as exc:
            failed[joint] = str(exc)
            print(f"  {exc}: not saved; the other joints go on", file=out, flush=True)
            continue
        if joint not in arm.continuous_joints:
            print(f"  {joint}: MIN {reading.low}  MAX {reading.high}", file=out, flush=True)
    flow.store(passed)
    motors = {**(kept or {}), **passed}
    if motors:
        save_calibration(output, {joint: motors[joint] for joint in arm.joints if joint in motors})
    missing = [joint for joint in arm.joints if joint not in motors]
    if not motors:
        print(f"no joint calibrated; nothing written to {output}", file=out, flush=True)
    elif missing:
        saved = len(arm.joints) - len(missing)
        print(
            f"calibration of {saved} of {len(arm.joints)} joints written to {output}; missing: {', '.join(missing)}",
            file=out,
            flush=True,
        )
    else:
        print(f"calibration written to {output}", file=out, flush=True)
    return failed
