"""A small rclpy program for DDS experiments across simulated hosts: talk, listen or watch the graph.

    python -m testsupport.dds_probe talk   --topic /probe --rate 20 [--size BYTES] [QoS options]
    python -m testsupport.dds_probe listen --topic /probe [QoS options]
    python -m testsupport.dds_probe graph  [--period 0.5]

It prints one JSON object per line on stdout: {"event": "ready"} once its node exists, then for
`talk` {"event": "sent", "seq": n} for each message, for `listen` {"event": "received", "seq": n,
"bytes": size} and {"event": "publishers", "count": n} whenever the number of publishers its graph
knows on the topic changes (looked at every --period), and for `graph` {"event": "graph", "nodes": [...], "topics": [...]}; every line carries
"t", CLOCK_MONOTONIC in seconds (one clock for all namespaces of the machine). Messages are
sensor_msgs/Image whose header.frame_id is the sequence number and whose data is `--size` bytes. It
runs until SIGINT or SIGTERM and then exits 0.
"""

import argparse
import json
import signal
import sys
import threading
import time

SPIN_SLICE_S = 0.05


def emit(event: str, **fields) -> None:
    print(json.dumps({"event": event, "t": time.monotonic(), **fields}), flush=True)


def qos_from(args):
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=args.depth,
        reliability=ReliabilityPolicy.RELIABLE if args.reliability == "reliable" else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL
        if args.durability == "transient_local"
        else DurabilityPolicy.VOLATILE,
    )


def talk(node, args) -> None:
    from sensor_msgs.msg import Image

    publisher = node.create_publisher(Image, args.topic, qos_from(args))
    payload = bytes(args.size)
    counter = iter(range(args.first_seq, sys.maxsize))

    def publish() -> None:
        seq = next(counter)
        message = Image()
        message.header.frame_id = str(seq)
        message.header.stamp = node.get_clock().now().to_msg()
        message.height, message.width, message.encoding, message.step = 1, len(payload), "mono8", len(payload)
        message.data = payload
        publisher.publish(message)
        emit("sent", seq=seq)

    node.create_timer(1.0 / args.rate, publish)


def listen(node, args) -> None:
    from sensor_msgs.msg import Image

    def receive(message) -> None:
        emit("received", seq=int(message.header.frame_id), bytes=len(message.data))

    node.create_subscription(Image, args.topic, receive, qos_from(args))
    publishers = [-1]

    def count() -> None:
        now = node.count_publishers(args.topic)
        if now != publishers[0]:
            publishers[0] = now
            emit("publishers", count=now)

    node.create_timer(args.period, count)


def graph(node, args) -> None:
    def report() -> None:
        nodes = sorted(f"{namespace.rstrip('/')}/{name}" for name, namespace in node.get_node_names_and_namespaces())
        topics = sorted(name for name, _ in node.get_topic_names_and_types())
        emit("graph", nodes=nodes, topics=topics)

    node.create_timer(args.period, report)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=["talk", "listen", "graph"])
    parser.add_argument("--topic", default="/probe")
    parser.add_argument("--name", default="")
    parser.add_argument("--rate", type=float, default=20.0)
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--first-seq", type=int, default=1, help="talk: the first sequence number")
    parser.add_argument("--depth", type=int, default=10)
    parser.add_argument("--reliability", choices=["reliable", "best_effort"], default="reliable")
    parser.add_argument("--durability", choices=["volatile", "transient_local"], default="volatile")
    parser.add_argument("--period", type=float, default=0.2, help="listen, graph: seconds between looks")
    args = parser.parse_args()

    import rclpy
    from rclpy.executors import SingleThreadedExecutor

    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    rclpy.init(signal_handler_options=rclpy.signals.SignalHandlerOptions.NO)
    node = rclpy.create_node(args.name or f"probe_{args.mode}")
    {"talk": talk, "listen": listen, "graph": graph}[args.mode](node, args)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    emit("ready")
    while not stop.is_set():
        executor.spin_once(timeout_sec=SPIN_SLICE_S)
    executor.shutdown(timeout_sec=0)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
