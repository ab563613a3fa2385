"""The control paths under hostile load: each measurement loads one part (the generated supervisor, the fleet
server) and prints its figures against a floor measured in the same run.

    .venv/bin/python bench/control.py [--quick]

Each measurement is the function `measure(quick: bool)` of its own module in bench/support/, named in
MEASUREMENTS (adding one is adding its module's name):
- control_load: control-socket requests/s and the loop's timer lateness with 1000 idle clients and with 30
  clients that never read their replies, against no other client.
- output_flood: supervisor CPU and peak memory while one node writes 100 MiB without a newline, against the
  same bytes in 80-byte lines and against `cat`.
- fleet_junk: fleet server memory while a Zenoh peer sends 20000 junk keys in 4 rounds, each forgotten
  before the next, against the idle server.
--quick: each measurement's own short run (phases of 0.5 s; a flood of 8 MiB; 2 rounds of 400 junk keys,
forgotten after 1.5 s), for the tests.
"""

import argparse
import importlib

MEASUREMENTS = [
    "control_load",
    "output_flood",
    "fleet_junk",
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short phases (seconds), for the test suite")
    options = parser.parse_args()
    for name in MEASUREMENTS:
        importlib.import_module(f"support.{name}").measure(options.quick)


if __name__ == "__main__":
    main()
