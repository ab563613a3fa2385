"""The command line of supervisor.py: parse options, run preflight, run the loop (or the listener)."""

import argparse
import shutil
import sys

from joshua_codegen.supervisor.common import log
from joshua_codegen.supervisor.loop import Supervisor
from joshua_codegen.supervisor.policy import EXIT_PREFLIGHT
from joshua_codegen.supervisor.preflight import preflight
from joshua_codegen.supervisor.robot import ROBOT
from joshua_codegen.supervisor.supervisord_listener import supervisord_listener


def positive_seconds(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds: {text}")
    return value


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=f"Run the nodes of robot {ROBOT['name']}.")
    parser.add_argument(
        "--skip-preflight", action="store_true", help="start even when devices, models or programs are missing"
    )
    parser.add_argument(
        "--duration",
        type=positive_seconds,
        metavar="SECONDS",
        help="stop with the shutdown cascade after this many seconds",
    )
    parser.add_argument(
        "--status-interval", type=positive_seconds, metavar="SECONDS", help="print one status line per node this often"
    )
    parser.add_argument(
        "--python",
        default=sys.executable or "python3",
        metavar="PATH",
        help="interpreter of Python entrypoints (default: the one running this script)",
    )
    parser.add_argument(
        "--no-cgroup",
        action="store_true",
        help="track the nodes' descendants through /proc even where a cgroup could hold them",
    )
    parser.add_argument("--supervisord-listener", action="store_true", help=argparse.SUPPRESS)
    options = parser.parse_args(argv)
    if "/" not in options.python:
        options.python = shutil.which(options.python) or options.python
    return options


def main(argv):
    options = parse_arguments(argv)
    if options.supervisord_listener:
        return supervisord_listener()
    supervisor = Supervisor(options)
    if not options.skip_preflight:
        problems = preflight(supervisor.nodes, options.python)
        if problems:
            log(
                "supervisor",
                f"preflight found {len(problems)} problem(s); nothing was started (--skip-preflight starts anyway):",
            )
            for problem in problems:
                print(f"  - {problem}", file=sys.stderr, flush=True)
            return EXIT_PREFLIGHT
    return supervisor.run()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
