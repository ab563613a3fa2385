"""`joshua-episode`: control a running recorder's episodes from a shell, see what it is doing, or drive it by keys.

    joshua-episode stop --robot /opt/joshua/so100_arm          # the robot's one DATA_SUBSCRIBER
    joshua-episode start --task "pick the cube" --node data_subscriber
    joshua-episode next | rerecord | discard                   # see episode_protocol.py
    joshua-episode status [--json]                             # phase, episode timer, frames, episodes saved
    joshua-episode keys                                        # -> next, <- re-record, Esc stop (episode_keys.py)

The command goes to the recorder's `/<node>/episode` topic in the robot's ROS domain (the manifest's
`ros_domain_id` with --robot, else ROS_DOMAIN_ID); the answer comes from its `/<node>/episode_state`
(episode_protocol.py) and is printed as one line, e.g. "saved episode 3 (412 frames) in /data/pick".
`status` prints the recorder's last progress report, e.g. "rec: recording episode 3 (task: pick the
cube): 12.3 s of 30 s, 368 frames; 3 episodes saved".

Exit codes: 0 done, 1 the recorder ignored the command or could not save the episode, 2 bad command
line or robot directory, 3 no recorder answered (none running under that name in that domain).
"""

import argparse
import json
import os
import sys
from pathlib import Path

from joshua_runtime.ai import episode_protocol as protocol

EXIT_OK, EXIT_REFUSED, EXIT_USAGE, EXIT_NO_RECORDER = 0, 1, 2, 3
ANSWER_TIMEOUT_S = 60.0  # how long saving an episode may take (a writer still loading LeRobot first loads it)
DISCOVERY_TIMEOUT_S = 10.0  # how long to wait for the recorder to be found (--discovery-timeout)
RECORDER_TYPE = "DATA_SUBSCRIBER"
VIEWS = ("status", "keys")


class UsageError(Exception):
    """A command line or robot directory this tool cannot use."""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="joshua-episode", description=__doc__.split("\n")[0])
    parser.add_argument("command", choices=[*protocol.COMMANDS, *VIEWS])
    parser.add_argument("--task", default="", help="task text of the episode `start` begins (default: the robot name)")
    parser.add_argument(
        "--node", default="", help="the recorder's node name (default: the robot's only DATA_SUBSCRIBER)"
    )
    parser.add_argument("--robot", metavar="OUT", help="the robot's build directory: its manifest gives the ROS domain")
    parser.add_argument("--json", action="store_true", help="status: print the progress report as JSON")
    parser.add_argument(
        "--timeout",
        type=float,
        default=ANSWER_TIMEOUT_S,
        metavar="SECONDS",
        help=f"how long to wait for the recorder's answer (default {ANSWER_TIMEOUT_S:g})",
    )
    parser.add_argument(
        "--discovery-timeout",
        type=float,
        default=DISCOVERY_TIMEOUT_S,
        metavar="SECONDS",
        help=f"how long to look for the recorder before giving up (default {DISCOVERY_TIMEOUT_S:g})",
    )
    options = parser.parse_args(argv)
    if options.task and options.command != "start":
        parser.error("--task goes with start")
    if options.json and options.command != "status":
        parser.error("--json goes with status")
    return options


def from_manifest(out: str, node: str) -> tuple[str, int | None]:
    """(recorder node name, ROS domain id or None) from a build directory's manifest.json."""
    path = Path(out) / "manifest.json"
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
        recorders = [n["name"] for n in manifest["nodes"] if n["type"] == RECORDER_TYPE]
        domain = manifest["robot"].get("ros_domain_id")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise UsageError(f"{path}: not a joshuac manifest ({exc})") from exc
    if node and node not in recorders:
        raise UsageError(f"{path}: no DATA_SUBSCRIBER named {node!r} (recorders: {', '.join(recorders) or 'none'})")
    if not node:
        if len(recorders) != 1:
            raise UsageError(
                f"{path}: {len(recorders)} DATA_SUBSCRIBER nodes ({', '.join(recorders) or 'none'}); "
                "name one with --node"
            )
        node = recorders[0]
    return node, domain


def command_text(options) -> str:
    return f"start {options.task}".strip() if options.command == "start" else options.command


def no_recorder(node: str, domain: int | None, discovery_s: float) -> str:
    shown = domain if domain is not None else os.environ.get("ROS_DOMAIN_ID", "0")
    return (
        f"joshua-episode: error: no recorder answers on /{node}/episode in ROS domain {shown} within "
        f"{discovery_s:g} s (is the robot running, and is {node} its DATA_SUBSCRIBER?)"
    )


def status(node: str, domain: int | None, as_json: bool, discovery_s: float) -> int:
    from joshua_runtime.ai.episode_client import RecorderClient, describe

    with RecorderClient(node, domain) as client:
        progress = client.wait_progress(discovery_s)
    if progress is None:
        print(no_recorder(node, domain, discovery_s), file=sys.stderr)
        return EXIT_NO_RECORDER
    print(json.dumps(dict(progress, node=node), sort_keys=True) if as_json else describe(node, progress))
    return EXIT_OK


def command(node: str, domain: int | None, text: str, discovery_s: float, timeout_s: float) -> int:
    from joshua_runtime.ai.episode_client import RecorderClient

    with RecorderClient(node, domain) as client:
        state = client.exchange(text, timeout_s) if client.found(discovery_s) else None
    if state is None:
        print(no_recorder(node, domain, discovery_s), file=sys.stderr)
        return EXIT_NO_RECORDER
    if not state:
        print(
            f"joshua-episode: error: {node} took the command but did not answer within {timeout_s:g} s", file=sys.stderr
        )
        return EXIT_NO_RECORDER
    message = state.get("message") or state["event"]
    if state["event"] in protocol.SUCCESS:
        print(f"{node}: {message}")
        return EXIT_OK
    print(f"joshua-episode: {node}: {message}", file=sys.stderr)
    return EXIT_REFUSED


def main(argv=None) -> int:
    try:
        options = parse_arguments(sys.argv[1:] if argv is None else argv)
    except SystemExit as exc:
        return EXIT_USAGE if exc.code else EXIT_OK
    try:
        node, domain = from_manifest(options.robot, options.node) if options.robot else (options.node, None)
        if not node:
            raise UsageError("name the recorder with --node NAME, or give the robot's build directory with --robot OUT")
    except UsageError as exc:
        print(f"joshua-episode: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    if options.command == "status":
        return status(node, domain, options.json, options.discovery_timeout)
    if options.command == "keys":
        from joshua_runtime.ai import episode_keys

        return episode_keys.run(node, domain, options.discovery_timeout)
    return command(node, domain, command_text(options), options.discovery_timeout, options.timeout)


if __name__ == "__main__":
    sys.exit(main())
