"""`supervisor.py ctl ...`: the control socket's command-line client."""

import argparse
import json
import socket
import sys

from joshua_codegen.supervisor.control import default_control_socket
from joshua_codegen.supervisor.robot import ROBOT

CTL_TIMEOUT_S = 30.0  # a restart waits for the node's stop cascade
CTL_EXIT_FAILED = 1


def ctl_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="supervisor.py ctl", description=f"Control the running robot {ROBOT['name']}."
    )
    parser.add_argument(
        "--control-socket",
        default=default_control_socket(ROBOT["name"]),
        metavar="PATH",
        help="the supervisor's socket (default: %(default)s)",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    status = commands.add_parser("status", help="every node's state")
    status.add_argument("--json", action="store_true", help="print the status as one JSON object")
    for action in ("restart", "stop", "start"):
        commands.add_parser(action, help=f"{action} one node").add_argument("node")
    logs = commands.add_parser("logs", help="the last lines of a node's output")
    logs.add_argument("node")
    logs.add_argument("-n", "--lines", type=int, default=100, help="how many lines (default 100)")
    logs.add_argument("-f", "--follow", action="store_true", help="then print new lines until interrupted")
    return parser.parse_args(argv)


def ctl(argv) -> int:
    options = ctl_arguments(argv)
    request = {"command": options.command}
    if options.command != "status":
        request["node"] = options.node
    if options.command == "logs":
        request.update(lines=options.lines, follow=options.follow)
    try:
        connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        connection.settimeout(CTL_TIMEOUT_S)
        connection.connect(options.control_socket)
        connection.sendall(json.dumps(request).encode() + b"\n")
        if options.follow if options.command == "logs" else False:
            connection.settimeout(None)
        replies = connection.makefile("rb")
        reply = json.loads(replies.readline() or b"{}")
        if not reply.get("ok"):
            print(f"supervisor.py ctl: error: {reply.get('error') or 'no answer'}", file=sys.stderr)
            return CTL_EXIT_FAILED
        print_reply(options, reply)
        if options.command == "logs" and options.follow:
            for line in replies:
                print(json.loads(line).get("line", ""), flush=True)
    except OSError as exc:
        print(
            f"supervisor.py ctl: error: control socket {options.control_socket}: {exc.strerror or exc}", file=sys.stderr
        )
        return CTL_EXIT_FAILED
    except KeyboardInterrupt:
        pass
    return 0


def print_reply(options, reply: dict) -> None:
    reply.pop("ok")
    if options.command == "status":
        if options.json:
            print(json.dumps(reply))
            return
        for node in reply["nodes"]:
            pid = f"pid {node['pid']}" if node["pid"] else "no process"
            print(f"{node['name']:24} {node['state']:9} {pid:12} {node['restarts']} restarts, {node['since_s']:.0f} s")
    elif options.command == "logs":
        for line in reply["lines"]:
            print(line)
    else:
        print(f"{reply['node']}: {reply['state']}" + (f" (pid {reply['pid']})" if reply["pid"] else ""))
