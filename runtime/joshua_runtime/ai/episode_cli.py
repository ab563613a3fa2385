"""`joshua-episode start|stop|discard`: control a running recorder's episodes from a shell and say what it did.

    joshua-episode stop --robot /opt/joshua/so100_arm          # the robot's one DATA_SUBSCRIBER
    joshua-episode start --task "pick the cube" --node data_subscriber

The command goes to the recorder's `/<node>/episode` topic in the robot's ROS domain (the manifest's
`ros_domain_id` with --robot, else ROS_DOMAIN_ID); the answer comes from its `/<node>/episode_state`
(episode_protocol.py) and is printed as one line, e.g. "saved episode 3 (412 frames) in /data/pick".

Exit codes: 0 done, 1 the recorder ignored the command or could not save the episode, 2 bad command
line or robot directory, 3 no recorder answered (none running under that name in that domain).
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

from joshua_runtime.ai import episode_protocol as protocol

EXIT_OK, EXIT_REFUSED, EXIT_USAGE, EXIT_NO_RECORDER = 0, 1, 2, 3
DISCOVERY_TIMEOUT_S = 10.0  # how long to wait for the recorder to be found (--discovery-timeout)
ANSWER_TIMEOUT_S = 60.0  # how long saving an episode may take (video encoding is finished at save)
SPIN_SLICE_S = 0.05
RECORDER_TYPE = "DATA_SUBSCRIBER"


class UsageError(Exception):
    """A command line or robot directory this tool cannot use."""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="joshua-episode", description=__doc__.split("\n")[0])
    parser.add_argument("command", choices=protocol.COMMANDS)
    parser.add_argument("--task", default="", help="task text of the episode `start` begins (default: the robot name)")
    parser.add_argument(
        "--node", default="", help="the recorder's node name (default: the robot's only DATA_SUBSCRIBER)"
    )
    parser.add_argument("--robot", metavar="OUT", help="the robot's build directory: its manifest gives the ROS domain")
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


def exchange(
    node_name: str, domain: int | None, text: str, answers: tuple[str, ...], discovery_s: float, answer_s: float
):
    """Send one command to the recorder and return its answering state; None when no recorder was found within
    `discovery_s`, {} when it was found but did not answer within `answer_s`."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    context = rclpy.Context()
    rclpy.init(context=context, **({"domain_id": domain} if domain is not None else {}))
    try:
        client = rclpy.create_node(f"joshua_episode_{os.getpid()}", context=context)
        states = []
        command_topic = f"/{node_name}/{protocol.COMMAND_TOPIC.removeprefix('~/')}"
        state_topic = f"/{node_name}/{protocol.STATE_TOPIC.removeprefix('~/')}"
        client.create_subscription(
            String, state_topic, lambda msg: states.append(protocol.decode(msg.data)), protocol.state_qos()
        )
        publisher = client.create_publisher(String, command_topic, protocol.COMMAND_QOS_DEPTH)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(client)

        def spin_until(condition, seconds):
            deadline = time.monotonic() + seconds
            while not condition() and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=SPIN_SLICE_S)
            return condition()

        if not spin_until(lambda: publisher.get_subscription_count() > 0 and any(states), discovery_s):
            return None
        baseline = max(state["seq"] for state in states if state)
        publisher.publish(String(data=text))

        def answer():
            return next((s for s in states if s and s["seq"] > baseline and s["event"] in answers), None)

        spin_until(answer, answer_s)
        return answer() or {}
    finally:
        rclpy.try_shutdown(context=context)


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
    shown_domain = domain if domain is not None else os.environ.get("ROS_DOMAIN_ID", "0")
    answers = protocol.ANSWERS[options.command]
    state = exchange(node, domain, command_text(options), answers, options.discovery_timeout, options.timeout)
    if state is None:
        print(
            f"joshua-episode: error: no recorder answers on /{node}/episode in ROS domain {shown_domain} within "
            f"{options.discovery_timeout:g} s (is the robot running, and is {node} its DATA_SUBSCRIBER?)",
            file=sys.stderr,
        )
        return EXIT_NO_RECORDER
    if not state:
        print(
            f"joshua-episode: error: {node} took the command but did not answer within {options.timeout:g} s",
            file=sys.stderr,
        )
        return EXIT_NO_RECORDER
    message = state.get("message") or state["event"]
    if state["event"] in protocol.SUCCESS:
        print(f"{node}: {message}")
        return EXIT_OK
    print(f"joshua-episode: {node}: {message}", file=sys.stderr)
    return EXIT_REFUSED


if __name__ == "__main__":
    sys.exit(main())
