"""`joshua-topic`: look at and talk to a robot's ROS topics (list, info, echo, hz, pub, play).

    joshua-topic list [-t]                           topics in the domain (with their types)
    joshua-topic info TOPIC [-v]                     types, publishers and subscriptions with their QoS
    joshua-topic echo TOPIC [--once | --count N] [--timeout S]   print messages as YAML
    joshua-topic hz TOPIC [--window N] [--duration S]   print the publishing rate every second
    joshua-topic pub TOPIC TYPE [YAML] [--rate HZ | --once | --times N]   publish a message
    joshua-topic play BAG [--rate R] [--loop] [--topics T ...] [--start S]   publish a recorded bag
    joshua-topic bag-recover IN OUT                  rewrite a bag cut short as an indexed one (no ROS)

`--robot OUT` takes the ROS domain from a build's OUT/manifest.json; otherwise ROS_DOMAIN_ID applies.
echo and hz wait for a publisher of the topic and subscribe with a QoS all its publishers serve:
reliable if all of them are, transient local (the messages they keep for late subscribers, such as
/tf_static, arrive at once) if all of them are. echo gives up when no message came within --timeout.
Exit codes: 0 success (also when stopped with Ctrl-C), 1 topic or publisher not found, or failure,
2 usage error, 3 echo received no message within --timeout.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import pathlib
import signal
import sys
import time
from collections import deque

from joshua_runtime.bags import play_command, recover_command

EXIT_USAGE = 2
EXIT_NO_MESSAGE = 3
DISCOVERY_S = 2.0  # how long `list` lets announcements arrive (no daemon holds the graph)
INFO_SETTLE_S = 1.0  # how long `info` keeps discovering once the topic has appeared, to find every endpoint
TOPIC_TIMEOUT_S = 10.0  # how long info and hz wait for the topic (and hz for a publisher) to appear
FIRST_MESSAGE_TIMEOUT_S = 10.0  # how long echo waits for its first message, the topic's discovery included
HZ_REPORT_EVERY_S = 1.0
HZ_WINDOW = 10000
PUB_MATCH_WAIT_S = 5.0  # how long a counted pub (--once, --times) waits for a subscription to match
FASTDDS_PROFILE = "fastdds_profile.xml"  # written by joshuac build beside the manifest
FASTDDS_PROFILE_VARIABLE = "FASTRTPS_DEFAULT_PROFILES_FILE"
PUB_LINGER_S = 0.3  # time for a one-shot message to leave before the process ends


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="joshua-topic", description=__doc__.splitlines()[0])
    parser.add_argument("--robot", metavar="OUT", help="a build directory; its manifest names the ROS domain")
    sub = parser.add_subparsers(dest="command", required=True)
    listing = sub.add_parser("list", help="list the topics of the domain")
    listing.add_argument("-t", "--show-types", action="store_true", help="print each topic's types")
    listing.add_argument("--wait", type=float, default=DISCOVERY_S, help="seconds of discovery (default %(default)s)")
    info = sub.add_parser("info", help="types, publishers and subscriptions of a topic with their QoS")
    info.add_argument("topic")
    info.add_argument(
        "--timeout", type=float, default=TOPIC_TIMEOUT_S, help="seconds to wait for the topic (0: forever)"
    )
    info.add_argument(
        "-v", "--verbose", action="store_true", help="also each endpoint's GID and timing QoS, and echo's QoS"
    )
    echo = sub.add_parser("echo", help="print the messages of a topic as YAML")
    echo.add_argument("topic")
    echo.add_argument("--once", action="store_true", help="print one message, then exit")
    echo.add_argument("--count", type=int, help="print this many messages, then exit")
    echo.add_argument("--full-arrays", action="store_true", help="print long arrays in full")
    echo.add_argument(
        "--timeout",
        type=float,
        default=FIRST_MESSAGE_TIMEOUT_S,
        metavar="S",
        help="seconds to wait for the first message, then exit 3 (0: forever; default %(default)s)",
    )
    hz = sub.add_parser("hz", help="print the publishing rate of a topic")
    hz.add_argument("topic")
    hz.add_argument("--window", type=int, default=HZ_WINDOW, help="messages the statistics cover")
    hz.add_argument("--duration", type=float, help="stop after this many seconds")
    hz.add_argument(
        "--timeout", type=float, default=TOPIC_TIMEOUT_S, help="seconds to wait for a publisher (0: forever)"
    )
    pub = sub.add_parser("pub", help="publish a message given as YAML")
    pub.add_argument("topic")
    pub.add_argument("type", help="message type, e.g. std_msgs/msg/String")
    pub.add_argument("values", nargs="?", default="{}", help='field values as YAML, e.g. "{data: hi}"')
    pub.add_argument("-r", "--rate", type=float, default=1.0, help="messages per second (default %(default)s)")
    pub.add_argument("-1", "--once", action="store_true", help="publish one message, then exit")
    pub.add_argument("-t", "--times", type=int, help="publish this many messages, then exit")
    pub.add_argument("--transient-local", action="store_true", help="keep the last message for late subscribers")
    pub.add_argument(
        "--wait-matching",
        type=float,
        default=PUB_MATCH_WAIT_S,
        metavar="S",
        help="with --once/--times, seconds to wait for a subscriber first (default %(default)s)",
    )
    play_command.register(sub)
    recover_command.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if getattr(args, "offline", None):  # a file tool: no ROS domain
        return args.offline(args)
    try:
        domain = _robot_domain(args.robot) if args.robot else None
        if args.robot:
            _use_robot_discovery_profile(args.robot)
    except UsageError as exc:
        print(f"joshua-topic: {exc}", file=sys.stderr)
        return EXIT_USAGE
    if getattr(args, "rate", 1.0) <= 0:
        print("joshua-topic: --rate must be above 0", file=sys.stderr)
        return EXIT_USAGE
    if getattr(args, "timeout", 0.0) < 0:
        print("joshua-topic: --timeout must be 0 (wait forever) or more", file=sys.stderr)
        return EXIT_USAGE

    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    from joshua_runtime.errors import JoshuaError
    from joshua_runtime.ros_node import create_ros_node
    from joshua_runtime.ros_teardown import leave_ros
    from joshua_runtime.tools.topic_graph import NoMessage

    # Ctrl-C (SIGINT) stops every command, also when it was started with SIGINT ignored (a shell's background
    # job, a test runner's worker): Python keeps an inherited SIG_IGN, and `play --loop` would never end.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain, signal_handler_options=SignalHandlerOptions.NO)
    node = create_ros_node(f"joshua_topic_{args.command}_{os.getpid()}", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    code = 1  # an exception this function does not handle ends the process with 1 too
    try:
        code = COMMANDS[args.command](node, executor, args) or 0
    except KeyboardInterrupt:
        code = 0
    except NoMessage as exc:
        print(f"joshua-topic: {exc}", file=sys.stderr)
        code = EXIT_NO_MESSAGE
    except JoshuaError as exc:
        print(f"joshua-topic: {exc}", file=sys.stderr)
        code = EXIT_USAGE if exc.exit_code == EXIT_USAGE else 1
    finally:
        leave_ros(executor, node, context, exit_code=code)
    return code


class UsageError(Exception):
    """The command line names something unusable (a build directory without a manifest)."""


def _robot_domain(out: str) -> int | None:
    """The ROS domain a build runs its robot in (None: the robot uses ROS_DOMAIN_ID as found)."""
    manifest = pathlib.Path(out) / "manifest.json"
    try:
        robot = json.loads(manifest.read_text(encoding="utf-8"))["robot"]
    except FileNotFoundError:
        raise UsageError(f"{out}: no manifest.json (give the output directory of `joshuac build`)") from None
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise UsageError(f"{manifest}: unreadable manifest ({exc})") from None
    return robot.get("ros_domain_id")


def _use_robot_discovery_profile(out: str) -> None:
    """Discover with the robot's own Fast DDS profile (its announcement timing), unless one is set already."""
    profile = pathlib.Path(out) / FASTDDS_PROFILE
    if profile.is_file():
        os.environ.setdefault(FASTDDS_PROFILE_VARIABLE, str(profile.resolve()))


def _list(node, executor, args) -> None:
    from joshua_runtime.tools.topic_graph import discover

    discover(executor, args.wait)
    for name, types in sorted(node.get_topic_names_and_types()):
        print(f"{name} [{', '.join(types)}]" if args.show_types else name)


def _info(node, executor, args) -> int:
    from joshua_runtime.tools.topic_graph import (
        describe_endpoint,
        describe_qos,
        discover,
        subscription_qos,
        wait_for_topic,
    )

    wait_for_topic(node, executor, args.topic, args.timeout)
    discover(executor, INFO_SETTLE_S)
    types = dict(node.get_topic_names_and_types())[args.topic]
    publishers = node.get_publishers_info_by_topic(args.topic)
    subscriptions = [
        info for info in node.get_subscriptions_info_by_topic(args.topic) if info.node_name != node.get_name()
    ]
    print(f"Type: {', '.join(types)}")
    print(f"Publisher count: {len(publishers)}")
    for info in publishers:
        print("\n" + describe_endpoint(info, args.verbose))
    print(f"\nSubscription count: {len(subscriptions)}")
    for info in subscriptions:
        print("\n" + describe_endpoint(info, args.verbose))
    if args.verbose and publishers:
        print(f"\necho and hz subscribe with: {describe_qos(subscription_qos(publishers))}")
    return 0


def _subscribe(node, executor, args, callback):
    """Subscribe to args.topic once a publisher of it is known, with a QoS all the known publishers
    serve; that QoS."""
    from joshua_runtime.messages import message_class
    from joshua_runtime.tools.topic_graph import subscription_qos, wait_for_publishers

    types, publishers = wait_for_publishers(node, executor, args.topic, args.timeout)
    qos = subscription_qos(publishers)
    node.create_subscription(message_class(types[0]), args.topic, callback, qos)
    return qos


def _echo(node, executor, args) -> None:
    from joshua_runtime.tools.message_text import to_yaml
    from joshua_runtime.tools.topic_graph import NoMessage, deadline_after, describe_qos, passed

    deadline = deadline_after(args.timeout)  # for the first message; discovering the topic counts
    wanted = 1 if args.once else args.count
    printed = 0

    def show(message) -> None:
        nonlocal printed
        if wanted is None or printed < wanted:
            sys.stdout.write(to_yaml(message, None if args.full_arrays else 128))
            sys.stdout.flush()
            printed += 1

    qos = _subscribe(node, executor, args, show)
    while wanted is None or printed < wanted:
        executor.spin_once(timeout_sec=0.1)
        if not printed and passed(deadline):
            # named now: discovery may learn an endpoint before the name of its node
            names = ", ".join(sorted({info.node_name for info in node.get_publishers_info_by_topic(args.topic)}))
            raise NoMessage(
                f"no message on {args.topic} within {args.timeout:g} s from its publishers ({names}), "
                f"subscribed {describe_qos(qos)}; --timeout S waits longer, 0 forever"
            )


def _hz(node, executor, args) -> None:
    arrivals: deque[float] = deque(maxlen=args.window + 1)
    _subscribe(node, executor, args, lambda _message: arrivals.append(time.monotonic()))
    started = time.monotonic()
    next_report = started + HZ_REPORT_EVERY_S
    while args.duration is None or time.monotonic() - started < args.duration:
        executor.spin_once(timeout_sec=0.05)
        if time.monotonic() >= next_report:
            next_report += HZ_REPORT_EVERY_S
            print(_rate_report(list(arrivals)) if len(arrivals) > 1 else "no new messages", flush=True)


def _rate_report(arrivals: list[float]) -> str:
    gaps = [later - earlier for earlier, later in itertools.pairwise(arrivals)]
    mean = sum(gaps) / len(gaps)
    deviation = math.sqrt(sum((gap - mean) ** 2 for gap in gaps) / len(gaps))
    return (
        f"average rate: {1.0 / mean:.3f}\n"
        f"\tmin: {min(gaps):.3f}s max: {max(gaps):.3f}s std dev: {deviation:.5f}s window: {len(arrivals)}"
    )


def _pub(node, executor, args) -> None:
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    from joshua_runtime.messages import message_class
    from joshua_runtime.tools.message_text import from_yaml, to_yaml

    message = from_yaml(message_class(args.type), args.values)
    durability = DurabilityPolicy.TRANSIENT_LOCAL if args.transient_local else DurabilityPolicy.VOLATILE
    publisher = node.create_publisher(
        type(message), args.topic, QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE, durability=durability)
    )
    times = 1 if args.once else args.times
    if times is not None:
        deadline = time.monotonic() + args.wait_matching
        while publisher.get_subscription_count() == 0 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
    print(f"publisher: beginning loop\npublishing #1: {to_yaml(message)}", end="", flush=True)
    sent = 0
    period = 1.0 / args.rate
    next_send = time.monotonic()
    while times is None or sent < times:
        now = time.monotonic()
        if now >= next_send:
            publisher.publish(message)
            sent += 1
            next_send += period
        executor.spin_once(timeout_sec=max(0.0, min(period, next_send - time.monotonic())))
    time.sleep(PUB_LINGER_S)


COMMANDS = {"list": _list, "info": _info, "echo": _echo, "hz": _hz, "pub": _pub, "play": play_command.run}

if __name__ == "__main__":
    sys.exit(main())
