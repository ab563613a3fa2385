"""Fleet server memory under junk: RSS idle (the floor), at its peak and after eviction, for 20000 junk keys
published in 4 rounds of 5000, each forgotten before the next.

    .venv/bin/python bench/fleet_memory.py [--keys 5000] [--rounds 4] [--forget-after 5] [--quick]

A real `joshua-fleet` on loopback and a real Zenoh peer publishing the junk (see support/fleet_junk.py).
The goal: memory after eviction flat from round to round and near the floor, the peak bounded.
--quick: 2 rounds of 1000 keys.
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support.fleet_junk import FORGET_AFTER_S, KEYS, ROUNDS, fleet_memory, measure  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keys", type=int, default=KEYS, help=f"junk keys per round (default {KEYS})")
    parser.add_argument("--rounds", type=int, default=ROUNDS, help=f"rounds (default {ROUNDS})")
    parser.add_argument(
        "--forget-after",
        type=float,
        default=FORGET_AFTER_S,
        help=f"the server's --forget-after (default {FORGET_AFTER_S:g})",
    )
    parser.add_argument("--quick", action="store_true", help="2 rounds of 1000 keys (for the tests)")
    args = parser.parse_args()
    if args.quick:
        measure(quick=True)
    else:
        print(fleet_memory(args.keys, args.rounds, args.forget_after).summary(), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
