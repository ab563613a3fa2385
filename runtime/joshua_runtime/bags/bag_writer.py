"""A rosbag2-compatible MCAP bag: serialized messages into `<bag>/<bag>_<n>.mcap` files plus metadata.yaml.

Each file is an MCAP file of profile `ros2`: schemas hold full `ros2msg` definitions, channels the
`cdr` message encoding, as rosbag2's MCAP storage writes them, so `ros2 bag`, Foxglove, `rosbags` and
mcap's own readers open it. A file is split when it holds `max_size_bytes` or spans `max_duration_ns`
(0: no limit). Chunks are finished at least every `CHUNK_FLUSH_PERIOD_S`, so a process killed without
warning leaves every message up to its last finished chunk readable; `close()` writes the summary
that makes the file indexed, and metadata.yaml lists the files (rewritten at every split and at close).
A write that fails (a full disk) may have written part of a record: `abandon()` cuts the file back to
its last whole record, so that streaming readers reach its end instead of failing on the torn record.
"""

from __future__ import annotations

import os
import pathlib
import time
from dataclasses import dataclass, field

import yaml
from mcap.well_known import MessageEncoding, Profile, SchemaEncoding
from mcap.writer import CompressionType, Writer

from joshua_runtime.bags.message_definitions import full_definition

CHUNK_SIZE_BYTES = 1024 * 1024
CHUNK_FLUSH_PERIOD_S = 1.0
METADATA_FILE = "metadata.yaml"
METADATA_VERSION = 5  # rosbag2's metadata format holding per-file entries; read by every rosbag2 since Humble
LIBRARY = "joshua_runtime bag writer"


@dataclass
class FileStats:
    path: str
    start_ns: int = 0
    end_ns: int = 0
    count: int = 0


@dataclass
class TopicStats:
    message_type: str
    offered_qos: str = ""  # bag_qos.py's text: the QoS its publishers offer, played back with it
    count: int = 0


@dataclass
class BagStats:
    files: list[FileStats] = field(default_factory=list)
    topics: dict[str, TopicStats] = field(default_factory=dict)


class BagWriter:
    """Writes one bag directory; `add_topic` each topic, then `write` serialized messages, then `close`."""

    def __init__(self, directory: pathlib.Path, max_size_bytes: int = 0, max_duration_ns: int = 0):
        self.directory = directory
        self.max_size_bytes = max_size_bytes
        self.max_duration_ns = max_duration_ns
        self.stats = BagStats()
        self._definitions: dict[str, bytes] = {}
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._file = None
        self._path: pathlib.Path | None = None  # the current file
        self._writer: Writer | None = None
        self._whole_bytes = 0  # the current file's length up to its last record known to be written whole
        self._last_flush = time.monotonic()
        directory.mkdir(parents=True, exist_ok=False)
        try:
            self._open_next_file()
        except OSError:
            self._remove_unstarted()
            raise

    def add_topic(self, topic: str, message_type: str, offered_qos: str = "") -> None:
        """Declare a topic, its `pkg/msg/Type` (its definition is looked up now) and its QoS (bag_qos.to_yaml).

        Its channel is written with its first message, so `offered_qos` may be corrected until then."""
        self._definitions[message_type] = full_definition(message_type).encode()
        self.stats.topics[topic] = TopicStats(message_type, offered_qos)

    def set_offered_qos(self, topic: str, offered_qos: str) -> None:
        """The QoS of a topic's publishers, learnt once they are known (before its first message is written)."""
        self.stats.topics[topic].offered_qos = offered_qos

    def write(self, topic: str, data: bytes, receive_time_ns: int) -> None:
        """Append one serialized (CDR) message of a declared topic."""
        current = self.stats.files[-1]
        if current.count and self._split_due(current, receive_time_ns):
            self._finish_file()
            self._open_next_file()
            current = self.stats.files[-1]
        if topic not in self._channels:
            self._register(topic)
        self._writer.add_message(
            self._channels[topic], log_time=receive_time_ns, data=data, publish_time=receive_time_ns
        )
        if self._file.tell() != self._whole_bytes:  # a full chunk was finished on the way
            self._mark_whole()
        if not current.count:
            current.start_ns = receive_time_ns
        current.end_ns = max(current.end_ns, receive_time_ns)
        current.count += 1
        self.stats.topics[topic].count += 1
        self.flush_if_due()

    def flush_if_due(self) -> None:
        """Finish the chunk in progress once it is CHUNK_FLUSH_PERIOD_S old (called on writes and by timers)."""
        if self._writer is not None and time.monotonic() - self._last_flush >= CHUNK_FLUSH_PERIOD_S:
            self._writer.flush()
            self._whole_bytes = self._file.tell()
            self._last_flush = time.monotonic()

    def close(self) -> None:
        """Write the summary of the last file and metadata.yaml; the bag is complete."""
        if self._writer is not None:
            self._finish_file()

    def abandon(self) -> None:
        """Close the file after a failed write, without a summary, cut back to its last whole record: it reads
        as a bag cut by a kill would, up to its last finished chunk (`joshua-topic bag-recover` indexes it)."""
        if self._file is not None:
            try:
                self._file.close()
            except OSError:  # the buffered rest cannot be written either
                pass
            try:
                os.truncate(self._path, self._whole_bytes)  # frees space, never needs it
            except FileNotFoundError:  # removed meanwhile: nothing left to cut
                pass
        self._writer = self._file = None

    def _remove_unstarted(self) -> None:
        """Remove what a bag that failed to start (a full disk) left: its directory, created by this writer, and
        the files it began there, none of which holds a message. A torn header would pass for a bag."""
        self.abandon()
        for path in (self._path, self.directory / METADATA_FILE, metadata_staging(self.directory)):
            if path is not None:
                path.unlink(missing_ok=True)
        self.directory.rmdir()

    def _split_due(self, current: FileStats, now_ns: int) -> bool:
        too_long = self.max_duration_ns and now_ns - current.start_ns >= self.max_duration_ns
        too_big = self.max_size_bytes and self._file.tell() >= self.max_size_bytes
        return bool(too_long or too_big)

    def _open_next_file(self) -> None:
        name = f"{self.directory.name}_{len(self.stats.files)}.mcap"
        self._path, self._whole_bytes = self.directory / name, 0
        self._file = open(self._path, "wb")  # noqa: SIM115 - open until the file is finished
        self._writer = Writer(self._file, chunk_size=CHUNK_SIZE_BYTES, compression=CompressionType.ZSTD)
        self._writer.start(profile=Profile.ROS2, library=LIBRARY)
        self.stats.files.append(FileStats(name))
        self._channels = {}
        self._schemas = {}
        for topic, topic_stats in self.stats.topics.items():
            if topic_stats.count:  # the others are registered with their first message
                self._register(topic)
        self._mark_whole()
        self._write_metadata()

    def _mark_whole(self) -> None:
        self._file.flush()
        self._whole_bytes = self._file.tell()

    def _register(self, topic: str) -> None:
        message_type = self.stats.topics[topic].message_type
        if message_type not in self._schemas:
            self._schemas[message_type] = self._writer.register_schema(
                name=message_type, encoding=SchemaEncoding.ROS2, data=self._definitions[message_type]
            )
        self._channels[topic] = self._writer.register_channel(
            topic=topic,
            message_encoding=MessageEncoding.CDR,
            schema_id=self._schemas[message_type],
            metadata={"offered_qos_profiles": self.stats.topics[topic].offered_qos},
        )

    def _finish_file(self) -> None:
        self._writer.finish()
        self._file.close()
        self._writer = self._file = None
        self._write_metadata()

    def _write_metadata(self) -> None:
        write_metadata(self.directory, self.stats)


def write_metadata(directory: pathlib.Path, stats: BagStats) -> None:
    """Write (atomically) the metadata.yaml of the bag at `directory` that `stats` describe."""
    files = [f for f in stats.files if f.count] or stats.files[:1]
    start = min((f.start_ns for f in files if f.count), default=0)
    end = max((f.end_ns for f in files), default=0)
    info = {
        "version": METADATA_VERSION,
        "storage_identifier": "mcap",
        "duration": {"nanoseconds": end - start},
        "starting_time": {"nanoseconds_since_epoch": start},
        "message_count": sum(f.count for f in stats.files),
        "topics_with_message_count": [
            {
                "topic_metadata": {
                    "name": topic,
                    "type": topic_stats.message_type,
                    "serialization_format": "cdr",
                    "offered_qos_profiles": topic_stats.offered_qos,
                },
                "message_count": topic_stats.count,
            }
            for topic, topic_stats in stats.topics.items()
        ],
        "compression_format": "",
        "compression_mode": "",
        "relative_file_paths": [f.path for f in stats.files],
        "files": [
            {
                "path": f.path,
                "starting_time": {"nanoseconds_since_epoch": f.start_ns},
                "duration": {"nanoseconds": f.end_ns - f.start_ns},
                "message_count": f.count,
            }
            for f in stats.files
        ],
    }
    staging = metadata_staging(directory)
    staging.write_text(yaml.safe_dump({"rosbag2_bagfile_information": info}, sort_keys=False))
    staging.replace(directory / METADATA_FILE)


def metadata_staging(directory: pathlib.Path) -> pathlib.Path:
    """Where metadata.yaml is written before it replaces the last one."""
    return directory / f".{METADATA_FILE}.tmp"
