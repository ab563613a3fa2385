"""The command line of supervisor.py: parse options, run preflight, run the loop (or the listener)."""

import argparse
import os
import sys

from joshua_codegen.supervisor.common import find_program, log, signal_name
from joshua_codegen.supervisor.control import CONTROL_SOCKET_VARIABLE
from joshua_codegen.supervisor.control_socket import control_name, default_control_socket
from joshua_codegen.supervisor.ctl import ctl
from joshua_codegen.supervisor.ctl_hosts import HOSTS_SOCKET_VARIABLE, hosts_socket_path
from joshua_codegen.supervisor.loop import Supervisor
from joshua_codegen.supervisor.node_log import default_log_dir
from joshua_codegen.supervisor.policy import EXIT_INTERNAL, EXIT_OK, EXIT_PREFLIGHT
from joshua_codegen.supervisor.preflight import preflight
from joshua_codegen.supervisor.robot import ROBOT
from joshua_codegen.supervisor.supervisord_listener import supervisord_listener

STOPPED_BEFORE_START = "received {signal} before any node started: nothing was started"


def positive_seconds(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds: {text}")
    return value


class StartHelpFormatter(argparse.HelpFormatter):
    """argparse's help layout for the terminal's width, which argparse itself would ask shutil for: importing shutil
    (and the compression modules it loads) costs every start about 1.5 ms, as argparse makes a formatter per option."""

    def __init__(self, prog):
        try:
            columns = int(os.environ.get("COLUMNS", "")) or os.get_terminal_size(sys.__stdout__.fileno()).columns
        except (ValueError, OSError, AttributeError):
            columns = 80
        super().__init__(prog, width=max(columns, 40) - 2)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        description=f"Run the nodes of robot {ROBOT['name']}.", formatter_class=StartHelpFormatter
    )
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
    parser.add_argument(
        "--no-node-starter",
        action="store_true",
        help="start each Python node in an interpreter of its own, instead of forking the Python nodes from one "
        "process that imported their node types once",
    )
    parser.add_argument(
        "--control-socket",
        default=default_control_socket(control_name(ROBOT)),
        metavar="PATH",
        help="serve the control socket here, in a directory of yours of mode 0700 (created when missing); "
        "the supervisor does not start without it (default: %(default)s; `ctl` is its client)",
    )
    parser.add_argument("--no-control", action="store_true", help="serve no control socket")
    parser.add_argument(
        "--log-dir",
        default=default_log_dir(ROBOT["name"]),
        metavar="DIR",
        help="keep each node's output in DIR/<node>.log, rotated (default: %(default)s)",
    )
    parser.add_argument("--supervisord-listener", action="store_true", help=argparse.SUPPRESS)
    options = parser.parse_args(argv)
    if "/" not in options.python:
        options.python = find_program(options.python, os.environ.get("PATH", os.defpath)) or options.python
    return options


def main(argv):
    if argv[:1] == ["ctl"]:
        return ctl(argv[1:])
    try:
        options = parse_arguments(argv)
        return supervise(options)
    except KeyboardInterrupt:  # Ctrl-C before supervise() took the stop signals: nothing started yet
        log("supervisor", STOPPED_BEFORE_START.format(signal="SIGINT"))
        return EXIT_OK
    except Exception:  # noqa: BLE001 (a bug before or after the loop, which handles its own: no traceback exit 1)
        import traceback

        log("supervisor", "internal error (a bug in supervisor.py); its traceback:")
        traceback.print_exc()
        return EXIT_INTERNAL


def supervise(options):
    if options.no_control:
        options.control_socket = None
    else:
        os.environ[CONTROL_SOCKET_VARIABLE] = os.path.abspath(options.control_socket)
        if ROBOT.get("host"):
            os.environ[HOSTS_SOCKET_VARIABLE] = hosts_socket_path(os.environ[CONTROL_SOCKET_VARIABLE])
    if options.supervisord_listener:
        return supervisord_listener()
    supervisor = Supervisor(options)
    supervisor.take_stop_signals()
    if not options.skip_preflight:
        problems = preflight(supervisor.nodes, options.python)
        if supervisor.requests:  # a stop during the preflight (its probe may have been stopped by it too)
            log("supervisor", STOPPED_BEFORE_START.format(signal=signal_name(supervisor.requests[0])))
            return EXIT_OK
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
