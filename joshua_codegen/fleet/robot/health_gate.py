"""health_gate.py: wait until the robot runs its current release with every node ready, or say why not.

Run on the robot by the generated playbooks after a switch (standard library only). With the start method
`supervisor` it asks the supervisor's control socket (`supervisor.py ctl status --json`): the robot is
healthy once the supervisor runs the release's build and every node is ready (a node that ran to its
end counts too), as its `ready: N of N nodes ready` line says. With `systemd` it asks systemctl: every
unit of the release active (runtime nodes are Type=notify, active once they said READY=1).

The robot must stay so for --settle seconds (3 by default) without a node restarting: a node that
starts, says it is ready and fails a moment later fails the gate. A node that failed for good, a
supervisor that exited, or a failed unit ends the wait at once; otherwise it ends after --timeout seconds. The last line printed is `ready: N of N nodes ready (...)` or the
one-line reason; the exit code is 0 or 1.
"""

import argparse
import json
import os
import subprocess
import sys
import time

from layout import RELEASE_DIGITS, paths
from starting import supervisor_pid

POLL_S = 0.5
SETTLE_S = 3.0  # every node ready, without a restart, this long before the gate passes
QUERY_TIMEOUT_S = 20.0  # one ctl or systemctl call on a busy robot
LOG_LINES_SHOWN = 1


class Unhealthy(Exception):
    """The robot will not become ready; the message says why."""


def last_lines(path: str, count: int = LOG_LINES_SHOWN) -> str:
    try:
        with open(path, "rb") as file:
            file.seek(0, os.SEEK_END)
            file.seek(max(0, file.tell() - 8192))
            lines = [line for line in file.read().decode("utf-8", "replace").splitlines() if line.strip()]
    except OSError:
        return ""
    return " | ".join(line.strip() for line in lines[-count:])


def supervisor_alive(root: str) -> bool:
    return supervisor_pid(paths(root)) is not None


def supervisor_status(args) -> dict | None:
    """`ctl status --json` of the supervisor, or None while its socket does not answer."""
    current = os.path.join(args.root, "current")
    command = [args.python, os.path.join(current, "supervisor.py"), "ctl"]
    socket = os.path.join(args.root, "run", f"{args.control or args.robot}.sock")
    command += ["--control-socket", socket, "status", "--json"]
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=QUERY_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return None
    if done.returncode != 0:
        return None
    try:
        return json.loads(done.stdout)
    except ValueError:
        return None


def supervisor_verdict(args, status: dict | None) -> str | None:
    """The ready line when the robot is ready, None while it may still become so; Unhealthy otherwise."""
    logs = os.path.join(args.root, "logs")
    if status is None:
        if not supervisor_alive(args.root):
            why = last_lines(os.path.join(logs, "supervisor.log"))
            raise Unhealthy(f"the supervisor exited: {why}" if why else "the supervisor exited")
        return None
    build = ((status.get("run") or {}).get("build") or "")[:RELEASE_DIGITS]
    if args.release and build != args.release:
        raise Unhealthy(f"the supervisor runs build {build or 'unknown'}, not release {args.release}")
    nodes = status.get("nodes") or []
    for node in nodes:
        if node.get("state") == "failed":
            why = last_lines(os.path.join(logs, f"{node.get('name')}.log"))
            raise Unhealthy(f"node {node.get('name')} failed" + (f": {why}" if why else ""))
    ready = [node for node in nodes if node.get("ready") or node.get("state") == "finished"]
    if nodes and len(ready) == len(nodes):
        return f"ready: {len(ready)} of {len(nodes)} nodes ready (build {build})"
    return None


def supervisor_waiting(status: dict | None) -> str:
    if status is None:
        return "the control socket does not answer"
    waiting = [node for node in status.get("nodes") or [] if not (node.get("ready") or node.get("state") == "finished")]
    shown = ", ".join(
        f"{node.get('name')} ({node.get('state')}, {node.get('restarts', 0)} restarts)" for node in waiting
    )
    return f"not ready: {shown}"


def unit_states(args) -> dict[str, dict]:
    """{unit: {ActiveState, SubState, Result}} of the current release's units."""
    units = sorted(os.listdir(os.path.join(args.root, "current", "systemd")))
    services = [unit for unit in units if unit.endswith(".service")]
    command = ["systemctl", "show", "--property=Id,ActiveState,SubState,Result", "--", *services]
    done = subprocess.run(command, capture_output=True, text=True, timeout=QUERY_TIMEOUT_S)
    states, unit = {}, {}
    for line in done.stdout.splitlines() + [""]:
        if not line.strip():
            if "Id" in unit:
                states[unit["Id"]] = unit
            unit = {}
            continue
        key, _, value = line.partition("=")
        unit[key] = value
    return states


def systemd_verdict(args, states: dict[str, dict]) -> str | None:
    for name, unit in sorted(states.items()):
        if unit.get("ActiveState") == "failed":
            raise Unhealthy(f"unit {name} failed ({unit.get('Result')}): see journalctl -u {name}")
    if states and all(unit.get("ActiveState") == "active" for unit in states.values()):
        return f"ready: {len(states)} of {len(states)} units active"
    return None


def systemd_waiting(states: dict[str, dict]) -> str:
    waiting = [
        f"{name} ({unit.get('ActiveState')}/{unit.get('SubState')})"
        for name, unit in sorted(states.items())
        if unit.get("ActiveState") != "active"
    ]
    return "not active: " + ", ".join(waiting)


def restarts(observed) -> tuple:
    """What changes when a node restarts: each node's restart counts (or each unit's state)."""
    if isinstance(observed, dict) and "nodes" in observed:
        return tuple(
            (n.get("name"), n.get("restarts"), n.get("manual_restarts"), n.get("pid")) for n in observed["nodes"]
        )
    return tuple(sorted((name, unit.get("ActiveState")) for name, unit in (observed or {}).items()))


def wait_ready(args) -> str:
    """Ready = every node ready, with no restart, for --settle seconds (a node that starts and then fails
    is not mistaken for ready); a failure ends the wait at once."""
    deadline = time.monotonic() + args.timeout
    started = time.monotonic()
    ready_since, seen = None, None
    while True:
        if args.start == "systemd":
            observed = unit_states(args)
            verdict, waiting = systemd_verdict(args, observed), systemd_waiting
        else:
            observed = supervisor_status(args)
            verdict, waiting = supervisor_verdict(args, observed), supervisor_waiting
        now = time.monotonic()
        if verdict is None or (ready_since is not None and restarts(observed) != seen):
            ready_since, seen = None, None
        elif ready_since is None:
            ready_since, seen = now, restarts(observed)
        elif now - ready_since >= args.settle:
            return f"{verdict}, {now - started:.1f} s"
        if now > deadline:
            raise Unhealthy(f"not ready after {args.timeout:g} s: {waiting(observed)}")
        time.sleep(POLL_S)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="health_gate.py", description=__doc__.splitlines()[0])
    parser.add_argument("--root", default="/opt/joshua")
    parser.add_argument("--robot", required=True)
    parser.add_argument("--control", default="", help="names the control socket (default: the robot)")
    parser.add_argument("--start", choices=("systemd", "supervisor"), required=True)
    parser.add_argument("--python", default="python3", help="interpreter that runs supervisor.py ctl")
    parser.add_argument("--release", default="", help="the release the robot must run (12 hex digits)")
    parser.add_argument("--timeout", type=float, required=True, help="seconds")
    parser.add_argument(
        "--settle", type=float, default=SETTLE_S, help=f"seconds every node stays ready (default {SETTLE_S:g})"
    )
    return parser.parse_args(argv)


def main(argv=None) -> int:
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        print(wait_ready(args), flush=True)
    except Unhealthy as exc:
        print(exc, flush=True)
        return 1
    except (OSError, subprocess.SubprocessError) as exc:
        print(f"the health check failed: {exc}", flush=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
