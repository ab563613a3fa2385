"""`joshua-topic play BAG [--rate R] [--loop] [--topics T ...] [--start S] [--delay S]`: publish a recorded bag.

The publishers are created first; after `--delay` seconds (time for running subscribers to discover
them) the messages go out with their recorded timing (bag_player.py). Prints what it plays and how
many messages it published; Ctrl-C stops it (exit 0).
"""

import pathlib

ACK_WAIT_S = 5.0  # at the end, how long reliable subscribers may take to acknowledge the last messages
DISCOVERY_DELAY_S = 1.0  # default --delay: subscribers on one machine discover a new publisher well within it


def register(sub) -> None:
    play = sub.add_parser("play", help="publish a recorded bag with its timing and QoS")
    play.add_argument("bag", help="a bag directory (with metadata.yaml) or one .mcap file")
    play.add_argument("-r", "--rate", type=float, default=1.0, help="speed factor (default %(default)s)")
    play.add_argument("-l", "--loop", action="store_true", help="start over after the last message, until Ctrl-C")
    play.add_argument("--topics", nargs="+", default=[], metavar="TOPIC", help="play only these topics")
    play.add_argument("--start", type=float, default=0.0, metavar="S", help="skip the first S seconds of the bag")
    play.add_argument(
        "--delay",
        type=float,
        default=DISCOVERY_DELAY_S,
        metavar="S",
        help="seconds between creating the publishers and the first message (default %(default)s)",
    )


def run(node, _executor, args) -> int:
    import time

    from rclpy.duration import Duration

    from joshua_runtime.bags.bag_player import PlayOptions, chosen_topics, create_publishers, play
    from joshua_runtime.bags.bag_reader import open_bag
    from joshua_runtime.errors import SettingsError

    if args.start < 0 or args.delay < 0:
        raise SettingsError("--start and --delay must be 0 or more")
    bag = open_bag(pathlib.Path(args.bag))
    topics = chosen_topics(bag, args.topics)
    publishers = create_publishers(node, bag, topics, args.rate)
    count = sum(bag.topics[topic].count for topic in topics)
    print(
        f"playing {bag.path}: {count} messages on {len(topics)} topics over {bag.duration_s:.3f} s"
        f"{f' at {args.rate:g}x' if args.rate != 1 else ''}{' in a loop' if args.loop else ''}",
        flush=True,
    )
    time.sleep(args.delay)
    published = play(bag, publishers, PlayOptions(topics, args.rate, args.start, args.loop))
    for publisher in publishers.values():  # a reliable message still in flight would die with the process
        publisher.wait_for_all_acked(Duration(seconds=ACK_WAIT_S))
    print(f"published {published} messages", flush=True)
    return 0
