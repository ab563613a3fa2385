"""What /diagnostics costs a servo node's control loop, on an emulated 6-servo bus at 1 Mbaud wire time.

    .venv/bin/python bench/servo_diagnostics.py [--seconds 2] [--quick]

Times three bus transactions back to back: the control tick's state read (one SYNC_READ of 6 bytes
per servo), the diagnostics read the nodes make once per diagnostics period (one SYNC_READ of the 15-byte
telemetry span per servo), and the alternative of interleaving one servo's READ of that span per
tick. It prints the median of each and what the diagnostics read adds to one second of a 100 Hz
loop. Wall clock on a shared machine: the emulator's thread and the OS scheduler are in every figure.
--quick: a quarter of a second per transaction.
"""

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from joshua_runtime.drivers.sts3215_status import read_status
from joshua_runtime.drivers.sts3215_table import STATE_BLOCK_ADDRESS, STATE_BLOCK_SIZE
from joshua_runtime.emulators.sts3215 import Sts3215Emulator
from joshua_runtime.servo_tools.bus import open_bus

IDS = [1, 2, 3, 4, 5, 6]
CONTROL_HZ = 100.0
DIAGNOSTICS_HZ = 1.0
QUICK_SECONDS = 0.25


def median_s(operation, seconds: float) -> float:
    times = []
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        start = time.perf_counter()
        operation()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="time spent on each transaction")
    parser.add_argument("--quick", action="store_true", help="a quarter of a second per transaction")
    args = parser.parse_args()
    seconds = QUICK_SECONDS if args.quick else args.seconds
    with tempfile.TemporaryDirectory() as directory, Sts3215Emulator(Path(directory) / "ttyBENCH", IDS) as emulator:
        with open_bus(str(emulator.link)) as bus:
            state = median_s(lambda: bus.sync_read_bytes(STATE_BLOCK_ADDRESS, STATE_BLOCK_SIZE, IDS), seconds)
            telemetry = median_s(lambda: read_status(bus, IDS), seconds)
            one_servo = median_s(lambda: read_status(bus, IDS[:1]), seconds)
    tick_s = 1.0 / CONTROL_HZ
    print(f"state SYNC_READ (6 servos x 6 bytes):      {state * 1e3:.3f} ms")
    print(f"telemetry SYNC_READ (6 servos x 15 bytes): {telemetry * 1e3:.3f} ms")
    print(f"one servo's telemetry READ:                {one_servo * 1e3:.3f} ms")
    print(
        f"diagnostics at {DIAGNOSTICS_HZ:g} Hz, one SYNC_READ per period: "
        f"{telemetry * DIAGNOSTICS_HZ * 100:.3f} % of bus time, one {CONTROL_HZ:g} Hz tick delayed by "
        f"{telemetry / tick_s * 100:.1f} % of its period once a second"
    )
    print(
        f"interleaved, one servo per {CONTROL_HZ:g} Hz tick: {one_servo * CONTROL_HZ * 100:.3f} % of bus time, "
        f"every tick {one_servo / tick_s * 100:.1f} % longer"
    )


if __name__ == "__main__":
    main()
