"""STS3215 emulator replies on a busy machine: late ones with the serving thread at normal and at real-time priority.

    .venv/bin/python bench/servo_replies.py [--pings 5000] [--hogs-per-core 3] [--quick]

An emulated bus answers PINGs from a driver transport in the same process (no retries counted as
answered) while HOGS_PER_CORE processes a core spin, as busy as a full test run. A reply is late when
it misses the drivers' window (REPLY_TIMEOUT_S plus its time on the wire): the driver then retries,
and after four misses reports "no answer". Printed per priority: pings, late replies, round trip p50,
p99 and max; then the late ratio of real-time to normal (0 when none came late). --quick: 300 pings, no hogs.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_transport import Expected, NoAnswer, SerialTransport
from joshua_runtime.emulators.sts3215 import Sts3215Emulator

HOG = "while 1: pass"
QUICK_PINGS = 300


def late_replies(realtime: bool, pings: int, directory: Path) -> tuple[int, list[float]]:
    """(late replies, sorted round trips in ms) of `pings` PINGs to an emulator at that priority."""
    with Sts3215Emulator(directory / f"ttyRT{int(realtime)}", ids=[1], realtime=realtime) as emulator:
        transport = SerialTransport(str(emulator.link), emulator.baud_rate)
        transport.open()
        round_trips = []
        try:
            for _ in range(pings):
                started = time.monotonic()
                try:
                    transport.transact(proto.encode(1, proto.INST_PING), [Expected(1, 0)])
                except NoAnswer:  # every attempt came late: counted in the timeouts, as a driver would report it
                    pass
                round_trips.append(1000 * (time.monotonic() - started))
        finally:
            transport.close()
        return transport.stats["timeouts"], sorted(round_trips)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pings", type=int, default=5000)
    parser.add_argument("--hogs-per-core", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a short run (for the tests)")
    args = parser.parse_args()
    pings = QUICK_PINGS if args.quick else args.pings
    hogs_per_core = 0 if args.quick else args.hogs_per_core  # the suite runs it beside other tests: no hogs there
    hogs = [subprocess.Popen([sys.executable, "-c", HOG]) for _ in range(hogs_per_core * os.cpu_count())]
    late = {}
    try:
        with tempfile.TemporaryDirectory(prefix="servo-replies-") as directory:
            print(f"{pings} PINGs each, {len(hogs)} CPU hogs on {os.cpu_count()} cores")
            for realtime in (False, True):
                late[realtime], trips = late_replies(realtime, pings, Path(directory))
                name = "real-time" if realtime else "normal"
                p50, p99 = trips[len(trips) // 2], trips[int(len(trips) * 0.99)]
                print(
                    f"  {name:9} late {late[realtime]:4} ({100 * late[realtime] / pings:.2f} %), "
                    f"round trip p50 {p50:.2f} ms, p99 {p99:.2f} ms, max {trips[-1]:.1f} ms"
                )
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    ratio = late[True] / late[False] if late[False] else float(late[True] > 0)
    print(f"late replies, real-time / normal: {ratio:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
