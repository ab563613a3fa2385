"""Read a rosbag2 MCAP bag (a bag directory with metadata.yaml, or one .mcap file): its topics, types, QoS and messages.

Only indexed files are read (those a recorder closed, or `joshua-topic bag-recover` rewrote): the
summary gives the topics and time span without reading every message. Messages come in log-time
order, file after file (the files of a split bag follow one another in time).
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field

import yaml
from mcap.exceptions import McapError
from mcap.reader import make_reader

from joshua_runtime.bags.bag_writer import METADATA_FILE
from joshua_runtime.errors import SettingsError

MCAP_SUFFIX = ".mcap"


@dataclass(frozen=True)
class BagTopic:
    name: str
    message_type: str
    offered_qos: str  # bag_qos.py's text ("" when the bag has none)
    count: int


@dataclass
class Bag:
    path: pathlib.Path
    files: list[pathlib.Path]
    topics: dict[str, BagTopic] = field(default_factory=dict)
    start_ns: int = 0
    end_ns: int = 0

    @property
    def duration_s(self) -> float:
        return (self.end_ns - self.start_ns) / 1e9

    def messages(self, topics: list[str], start_ns: int = 0):
        """(topic, serialized message, log time in ns) of the chosen topics from `start_ns` on, in time order."""
        for path in self.files:
            with open(path, "rb") as stream:
                reader = make_reader(stream)
                for _schema, channel, message in reader.iter_messages(
                    topics=topics, start_time=start_ns or None, log_time_order=True
                ):
                    yield channel.topic, message.data, message.log_time


def bag_files(path: pathlib.Path) -> list[pathlib.Path]:
    """The MCAP files of a bag, in recording order; SettingsError when `path` is no bag."""
    if path.is_file():
        return [path]
    if not path.is_dir():
        raise SettingsError(f"{path}: no such bag (give a bag directory or an .mcap file)")
    metadata = path / METADATA_FILE
    if metadata.is_file():
        try:
            info = yaml.safe_load(metadata.read_text())["rosbag2_bagfile_information"]
            names = info["relative_file_paths"]
        except (OSError, yaml.YAMLError, KeyError, TypeError) as exc:
            raise SettingsError(f"{metadata}: unreadable bag metadata ({exc})") from None
        files = [path / name for name in names if (path / name).is_file()]
    else:
        files = sorted(path.glob(f"*{MCAP_SUFFIX}"))
    if not files:
        raise SettingsError(f"{path}: no {MCAP_SUFFIX} file in this bag")
    return files


def open_bag(path: pathlib.Path) -> Bag:
    """A bag's files, topics (type, QoS, message count) and time span, from the files' summaries."""
    bag = Bag(path, bag_files(path))
    starts, ends, counts = [], [], {}
    for file in bag.files:
        try:
            with open(file, "rb") as stream:
                summary = make_reader(stream).get_summary()
        except (OSError, McapError, ValueError) as exc:
            raise SettingsError(f"{file}: not a readable MCAP file ({exc})") from None
        if summary is None or summary.statistics is None:
            raise SettingsError(f"{file} has no index (cut short?); `joshua-topic bag-recover` makes an indexed copy")
        statistics = summary.statistics
        if statistics.message_count:
            starts.append(statistics.message_start_time)
            ends.append(statistics.message_end_time)
        for channel_id, channel in summary.channels.items():
            schema = summary.schemas.get(channel.schema_id)
            counts[channel.topic] = counts.get(channel.topic, 0) + statistics.channel_message_counts.get(channel_id, 0)
            if channel.topic not in bag.topics:
                bag.topics[channel.topic] = BagTopic(
                    channel.topic,
                    schema.name if schema else "",
                    channel.metadata.get("offered_qos_profiles", ""),
                    0,
                )
    bag.topics = {name: BagTopic(t.name, t.message_type, t.offered_qos, counts[name]) for name, t in bag.topics.items()}
    bag.start_ns, bag.end_ns = min(starts, default=0), max(ends, default=0)
    return bag
