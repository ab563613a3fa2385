"""`supervisor.py ctl ...`: the control socket's command-line client."""

import argparse
import os
import socket
import sys
import time

from joshua_codegen.supervisor.control_request import CONTROL_LOG_LINES_DEFAULT, CONTROL_LOG_LINES_MAX
from joshua_codegen.supervisor.control_socket import control_name, default_control_socket, may_control, peer_credentials
from joshua_codegen.supervisor.ctl_hosts import (
    UNREACHABLE_KIND,
    WAIT_FIELD,
    hosts_socket_path,
    hosts_usage_problem,
    print_all_hosts,
)
from joshua_codegen.supervisor.policy import STOP_EXTENSION_MAX_S
from joshua_codegen.supervisor.robot import ROBOT, SIGINT_GRACE_S, SIGTERM_GRACE_S
from joshua_codegen.supervisor.run_mark import BUILD_SHOWN_DIGITS

CTL_TIMEOUT_S = 30.0  # an answer on a busy machine, beyond what the robot's own waits take
# A command that stops nodes is answered once they have stopped: their SIGINT grace, or as long as a stopping node
# asks for more time (up to STOP_EXTENSION_MAX_S after its SIGINT), then their SIGTERM grace.
CTL_STOPPING_COMMANDS = ("stop", "restart", "reload")
CTL_STOPPING_TIMEOUT_S = max(SIGINT_GRACE_S, STOP_EXTENSION_MAX_S) + SIGTERM_GRACE_S + CTL_TIMEOUT_S
CTL_CONNECT_RETRY_S = 0.05  # while the socket's queue of waiting clients is full, try again this often
# Exit codes of `ctl`. A refusal is any error reply of the supervisor (its kind, see REFUSAL_KINDS, among them a
# start of a running node and a stop of a stopped one, both conflicts); usage errors are argparse's own code.
CTL_EXIT_DONE = 0
CTL_EXIT_REFUSED = 1
CTL_EXIT_USAGE = 2  # bad command line: argparse exits with it
CTL_EXIT_UNREACHABLE = 3  # no supervisor at the socket, one of another user, or no answer in time
CTL_EXIT_INTERRUPTED = 130  # Ctrl-C before the answer came (following a log, Ctrl-C is its normal end: 0)


def log_line_count(text: str) -> int:
    """The value of `logs -n`: a whole number of lines a request may ask for, else a usage error."""
    try:
        count = int(text)
    except ValueError:
        count = -1
    if not 0 <= count <= CONTROL_LOG_LINES_MAX:
        raise argparse.ArgumentTypeError(f"must be a whole number from 0 to {CONTROL_LOG_LINES_MAX}: {text}")
    return count


def ctl_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="supervisor.py ctl", description=f"Control the running robot {ROBOT['name']}."
    )
    parser.add_argument(
        "--control-socket",
        default=default_control_socket(control_name(ROBOT)),
        metavar="PATH",
        help="the supervisor's socket (default: %(default)s)",
    )
    parser.add_argument(
        "--host",
        metavar="NAME",
        help="a robot on several hosts: ask the supervisor of host NAME, through this host's agent (ctl_hosts.py)",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    status = commands.add_parser("status", help="every node's state")
    status.add_argument("--json", action="store_true", help="print the status as one JSON object")
    status.add_argument(
        "--all-hosts", action="store_true", help="a robot on several hosts: every host's nodes, each with its host"
    )
    for action in ("restart", "stop", "start"):
        commands.add_parser(action, help=f"{action} one node").add_argument("node")
    logs = commands.add_parser("logs", help="the last lines of a node's output in this run, each after its time")
    logs.add_argument("node")
    logs.add_argument(
        "-n", "--lines", type=log_line_count, default=CONTROL_LOG_LINES_DEFAULT, help="how many (default %(default)s)"
    )
    logs.add_argument("-f", "--follow", action="store_true", help="then print new lines until interrupted")
    logs.add_argument(
        "--all", action="store_true", help="from earlier runs too (each begins with its header line), as far as kept"
    )
    reload = commands.add_parser(
        "reload", help="apply a newer build of this robot: restart what changed, start what is new, stop what is gone"
    )
    reload.add_argument("build", metavar="OUT", help="the new build's directory (where its supervisor.py is)")
    options = parser.parse_args(argv)
    problem = hosts_usage_problem(options)
    if problem:
        parser.error(problem)
    return options


def ctl(argv) -> int:
    import json

    options = ctl_arguments(argv)
    request = {"command": options.command}
    if options.command == "reload":
        request["path"] = os.path.abspath(options.build)
    elif options.command != "status":
        request["node"] = options.node
    if options.command == "logs":
        request.update(lines=options.lines, follow=options.follow, all=options.all)
    path, what = options.control_socket, "control socket"
    if options.host or getattr(options, "all_hosts", False):
        path, what = hosts_socket_path(options.control_socket), "the host agent's socket"
        request.update({"host": options.host} if options.host else {"all_hosts": True})
        if options.command in CTL_STOPPING_COMMANDS:
            request[WAIT_FIELD] = CTL_STOPPING_TIMEOUT_S  # the agents wait as long for another host's answer
    following = options.command == "logs" and options.follow
    try:
        connection = ctl_connect(path)
        _, uid, _ = peer_credentials(connection)
        if not may_control(uid):
            print(
                f"supervisor.py ctl: error: {what} {path} is served by uid {uid}, "
                f"not by uid {os.geteuid()} or root: not talking to it",
                file=sys.stderr,
            )
            return CTL_EXIT_UNREACHABLE
        try:
            connection.sendall(json.dumps(request).encode() + b"\n")
        except (BrokenPipeError, ConnectionResetError):
            pass  # refused and closed at once (too many clients): the reply already sent says why
        if following:
            connection.settimeout(None)
        elif options.command in CTL_STOPPING_COMMANDS:
            connection.settimeout(CTL_STOPPING_TIMEOUT_S)
        replies = connection.makefile("rb")
        answer = replies.readline()
        if not answer:
            raise ValueError("it closed the connection without one")
        reply = json.loads(answer)
        if not reply.get("ok"):
            print(f"supervisor.py ctl: error: {reply.get('error') or 'refused, without a reason'}", file=sys.stderr)
            return CTL_EXIT_UNREACHABLE if reply.get("kind") == UNREACHABLE_KIND else CTL_EXIT_REFUSED
        print_reply(options, reply)
        if following:
            for line in replies:
                print(json.loads(line).get("line", ""), flush=True)
    except OSError as exc:
        print(f"supervisor.py ctl: error: {what} {path}: {exc.strerror or exc}", file=sys.stderr)
        return CTL_EXIT_UNREACHABLE
    except ValueError as exc:
        print(f"supervisor.py ctl: error: {what} {path}: no answer ({exc})", file=sys.stderr)
        return CTL_EXIT_UNREACHABLE
    except KeyboardInterrupt:
        return CTL_EXIT_DONE if following else CTL_EXIT_INTERRUPTED
    return CTL_EXIT_DONE


def ctl_connect(path: str) -> socket.socket:
    """A connection to the control socket, waiting up to CTL_TIMEOUT_S while its queue is full."""
    deadline = time.monotonic() + CTL_TIMEOUT_S
    while True:
        connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        connection.settimeout(CTL_TIMEOUT_S)
        try:
            connection.connect(path)
            return connection
        except BlockingIOError:
            connection.close()
            if time.monotonic() >= deadline:
                raise
            time.sleep(CTL_CONNECT_RETRY_S)


def print_reply(options, reply: dict) -> None:
    import json

    reply.pop("ok")
    if options.command == "status":
        if options.json:
            print(json.dumps(reply))
            return
        if options.all_hosts:
            print_all_hosts(reply)
            return
        for node in reply["nodes"]:
            pid = f"pid {node['pid']}" if node["pid"] else "no process"
            asked = f", {node['manual_restarts']} asked for" if node["manual_restarts"] else ""
            print(
                f"{node['name']:24} {node['state']:9} {pid:12} {node['restarts']} restarts{asked}, {node['since_s']:.0f} s"
            )
    elif options.command == "logs":
        for line in reply["lines"]:
            print(line)
    elif options.command == "reload":
        print_reload(reply)
    else:
        print(f"{reply['node']}: {reply['state']}" + (f" (pid {reply['pid']})" if reply["pid"] else ""))


def print_reload(reply: dict) -> None:
    """A reload's answer: the builds, then one line per node it restarted, started, stopped or updated."""
    builds = " -> ".join((digest or "unknown")[:BUILD_SHOWN_DIGITS] for digest in (reply["previous"], reply["build"]))
    print(f"reloaded robot {reply['robot']}: build {builds}")
    for node in reply["restarted"]:
        print(f"restarted {node['name']} ({node['why']})")
    for name in reply["started"]:
        print(f"started {name}")
    for name in reply["stopped"]:
        print(f"stopped {name}")
    for node in reply["updated"]:
        print(f"updated {node['name']} ({node['what']})")
    print(f"unchanged: {', '.join(reply['unchanged']) or 'none'}")
    for note in reply["notes"]:
        print(f"note: {note}")
