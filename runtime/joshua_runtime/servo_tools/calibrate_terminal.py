"""`joshua-servo calibrate`: the guided calibration in a terminal, Enter to advance, live MIN/POS/MAX."""

import select
import sys
import time
from pathlib import Path

from joshua_runtime.drivers.calibration import save_calibration
from joshua_runtime.servo_tools.calibration_flow import CalibrationFlow

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


def calibrate(bus, arm, output: Path, out=sys.stdout, stdin=sys.stdin) -> dict:
    """Run the flow joint by joint, then write `output`; returns the calibration."""
    flow = CalibrationFlow(bus, arm)
    flow.start()
    for joint in arm.joints:
        print(f"{arm.homing_instruction(joint)} Press Enter.", file=out, flush=True)
        wait_for_enter(stdin)
        flow.home(joint)
        if joint in arm.continuous_joints:
            print(arm.sweep_instruction(joint), file=out, flush=True)
            continue
        print(f"{arm.sweep_instruction(joint)} Press Enter when done.", file=out, flush=True)
        while not enter_pressed(stdin):
            reading = flow.sample(joint)
            if out.isatty():
                print(f"\r  MIN {reading.low:5d}  POS {reading.position:5d}  MAX {reading.high:5d}", end="", file=out)
            time.sleep(SAMPLE_PERIOD_S)
        reading = flow.sample(joint)
        print(f"  {joint}: MIN {reading.low}  MAX {reading.high}", file=out, flush=True)
    motors = flow.finish()
    save_calibration(output, motors)
    print(f"calibration written to {output}", file=out, flush=True)
    return motors
