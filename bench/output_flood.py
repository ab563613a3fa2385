"""Supervisor CPU while one node writes 100 MiB without a newline, against the same with newlines (the floor).

    .venv/bin/python bench/output_flood.py [--quick]     # --quick: 8 MiB (for the tests)

The measurement is bench/support/output_flood.py (see its docstring).
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from support.output_flood import output_flood  # noqa: E402

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 MiB rather than 100 MiB (for the tests)")
    output_flood(parser.parse_args().quick)
