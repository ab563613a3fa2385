"""DATA_SUBSCRIBER with output_format "mcap": record topic_name and input_topics, any type, into a ROS bag.

Settings used: `topic` and `inputs` (types learnt from the graph when the description has no
publisher), `output_directory` (each start writes a new bag directory `<robot>_<UTC time>` inside it),
`bag_max_size_mb` and `bag_max_duration_s` (split the bag into files; 0: no split). Messages are
taken serialized, as DDS delivers them, and stored as they are, each topic with the QoS its
publishers offer (bag_qos.py, learnt at its first message), which `joshua-topic play` publishes it with. SIGINT/SIGTERM close the bag (summary
and metadata.yaml); after SIGKILL the files stay readable up to their last finished chunk (by a
streaming reader; `joshua-topic bag-recover`, bag_recover.py, rewrites them indexed). The
first write that fails (a full disk) ends the node at once with exit code 6 and one line; the bag is
then left as a kill leaves it.
"""

import time
from pathlib import Path

from joshua_runtime.bags import bag_qos
from joshua_runtime.bags.bag_writer import CHUNK_FLUSH_PERIOD_S, BagWriter
from joshua_runtime.errors import DataLostError, SettingsError
from joshua_runtime.graph import with_discovered_types
from joshua_runtime.messages import message_class
from joshua_runtime.node import JoshuaNode
from joshua_runtime.qos import qos_profile

BYTES_PER_MB = 1_000_000
NS_PER_S = 1_000_000_000


def new_bag_directory(root: Path, prefix: str) -> Path:
    """`root/<prefix>_<UTC time>`, suffixed _2, _3 ... when a bag of that second exists (a quick restart)."""
    base = f"{prefix}_{time.strftime('%Y_%m_%d-%H_%M_%S', time.gmtime())}"
    candidate, number = root / base, 1
    while candidate.exists():
        number += 1
        candidate = root / f"{base}_{number}"
    return candidate


class BagRecorderNode(JoshuaNode):
    """Subscribes to every recorded topic in raw (serialized) form and writes each message to a BagWriter."""

    def start(self) -> None:
        self.write_failed = False
        if not self.settings.output_directory:
            raise SettingsError(f"{self.name}: output_directory is empty")
        topics = [self.settings.topic] if self.settings.HasField("topic") else []
        topics = with_discovered_types(self.ros, [*topics, *self.settings.inputs])
        if not topics:
            raise SettingsError(f"{self.name}: no topic to record (set topic_name or input_topics)")
        root = Path(self.settings.output_directory).expanduser()
        if root.exists() and not root.is_dir():
            raise SettingsError(f"output_directory {root} is not a directory")
        try:
            self.writer = BagWriter(
                new_bag_directory(root, self.settings.robot or self.name),
                self.settings.bag_max_size_mb * BYTES_PER_MB,
                round(self.settings.bag_max_duration_s * NS_PER_S),
            )
        except OSError as exc:
            raise DataLostError(f"cannot create a bag in {root}: {exc}") from exc
        self.subscriptions = []
        self.described_qos = {}
        for topic in topics:
            qos = self.described_qos[topic.name] = qos_profile(topic.qos)
            self.writer.add_topic(topic.name, topic.message_type, bag_qos.to_yaml([qos]))
            self.subscriptions.append(
                self.ros.create_subscription(
                    message_class(topic.message_type), topic.name, self._writer_of(topic.name), qos, raw=True
                )
            )
        self.flush_timer = self.ros.create_timer(CHUNK_FLUSH_PERIOD_S, lambda: self._written(self.writer.flush_if_due))
        self.log.info(f"recording {len(topics)} topics into the bag {self.writer.directory}")

    def _written(self, write, *arguments) -> None:
        """Run one write of the bag; the first that fails ends the recording with DataLostError (exit 6)."""
        try:
            write(*arguments)
        except OSError as exc:
            self.write_failed = True
            raise DataLostError(f"cannot write to the bag {self.writer.directory}: {exc}") from exc

    def _writer_of(self, topic: str):
        def write(data) -> None:
            if not self.writer.stats.topics[topic].count:
                self.writer.set_offered_qos(topic, bag_qos.to_yaml(self._offered_qos(topic)))
            self._written(self.writer.write, topic, data, time.time_ns())

        return write

    def _offered_qos(self, topic: str) -> list:
        """What the topic's publishers offer (known once one of their messages arrived), else the description's QoS."""
        described = self.described_qos[topic]
        offered = [info.qos_profile for info in self.ros.get_publishers_info_by_topic(topic)]
        for profile in offered:  # discovery does not tell a publisher's history: the description's stands in
            profile.history, profile.depth = described.history, described.depth
        return offered or [described]

    def close(self) -> None:
        writer = getattr(self, "writer", None)
        if writer is None:
            return
        if self.write_failed:  # reported already; a summary would fail the same way
            writer.abandon()
            self.log.info(
                f"bag {writer.directory} left readable up to its last finished chunk; "
                "`joshua-topic bag-recover` makes an indexed copy"
            )
            return
        try:
            writer.close()
        except OSError as exc:
            raise DataLostError(f"cannot finish the bag {writer.directory}: {exc}") from exc
        counts = ", ".join(f"{topic}: {stats.count}" for topic, stats in writer.stats.topics.items())
        self.log.info(f"bag {writer.directory} closed ({len(writer.stats.files)} files; {counts})")
