"""`joshua-topic bag-recover IN OUT`: rewrite a bag cut short (SIGKILL, power loss, full disk) as an indexed one.

A cut MCAP file has no summary, so readers that seek (mcap's `make_reader`, `ros2 bag`, Foxglove's
file view) refuse it, and only a streaming reader gets at its messages. Recovery reads the file as a
stream, record by record, up to its last whole chunk (a chunk whose CRC fails, or that stops half way,
ends the file), and writes every schema, channel, message, attachment and metadata record it found
into a new file with a summary and indexes, in the same order and with the same times. IN is an MCAP
file (OUT: the new file) or a bag directory (OUT: a new bag directory, one recovered file per file of
IN, and a metadata.yaml with the counts found). OUT must not exist; IN is never changed.
"""

from __future__ import annotations

import pathlib
import shutil
from dataclasses import dataclass, field

from mcap.exceptions import McapError
from mcap.records import Attachment, Channel, DataEnd, Header, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from joshua_runtime.bags.bag_writer import CHUNK_SIZE_BYTES, BagStats, FileStats, TopicStats, write_metadata
from joshua_runtime.errors import JoshuaError, SettingsError

MCAP_SUFFIX = ".mcap"
LIBRARY_SUFFIX = " (recovered by joshua-topic bag-recover)"


class RecoveryError(JoshuaError):
    """IN cannot be recovered: not an MCAP file, or not even its header is readable."""


@dataclass
class RecoveredFile:
    """What one file held: messages per topic (with their types), times, and where reading stopped."""

    path: pathlib.Path
    topics: dict[str, TopicStats] = field(default_factory=dict)
    start_ns: int = 0
    end_ns: int = 0
    complete: bool = False  # the file had its data end record: nothing was cut

    @property
    def messages(self) -> int:
        return sum(topic.count for topic in self.topics.values())


def recover(source: pathlib.Path, target: pathlib.Path) -> list[RecoveredFile]:
    """Recover the file or bag directory `source` into `target` (which must not exist)."""
    if target.exists():
        raise SettingsError(f"{target} exists; choose a new name for the recovered bag")
    if not source.is_dir() and not source.is_file():
        raise SettingsError(f"{source} is neither an MCAP file nor a bag directory")
    try:
        return _recover_bag(source, target) if source.is_dir() else [recover_file(source, target)]
    except BaseException:  # no half-written OUT is left behind (it did not exist before)
        if target.is_dir():
            shutil.rmtree(target, ignore_errors=True)
        else:
            target.unlink(missing_ok=True)
        raise


def recover_file(source: pathlib.Path, target: pathlib.Path) -> RecoveredFile:
    """Write the readable part of the MCAP file `source` as the indexed MCAP file `target`."""
    result = RecoveredFile(source)
    with open(source, "rb") as stream:
        records = StreamReader(stream, validate_crcs=True).records
        header = _first_record(records, source)
        with open(target, "xb") as output:
            writer = Writer(output, chunk_size=CHUNK_SIZE_BYTES, compression=CompressionType.ZSTD)
            writer.start(profile=header.profile, library=header.library + LIBRARY_SUFFIX)
            try:
                _copy(records, writer, result)
            except (McapError, ValueError):  # the cut: a record that stops half way or is garbled
                pass
            writer.finish()
    return result


def _first_record(records, source: pathlib.Path) -> Header:
    try:
        header = next(records)
    except (McapError, ValueError, StopIteration) as exc:
        raise RecoveryError(f"{source} is not an MCAP file ({type(exc).__name__}: {exc})") from None
    if not isinstance(header, Header):
        raise RecoveryError(f"{source} does not start with an MCAP header")
    return header


def _copy(records, writer: Writer, result: RecoveredFile) -> None:
    """Copy data records to `writer` until the data end record (or an exception at the cut)."""
    schemas: dict[int, int] = {}  # id in the source -> id in the target
    channels: dict[int, tuple[int, str]] = {}  # id in the source -> (id in the target, topic)
    names: dict[int, str] = {}  # schema id in the source -> schema name (the message type)
    for record in records:
        if isinstance(record, DataEnd):
            result.complete = True
            return
        if isinstance(record, Schema) and record.id not in schemas:
            schemas[record.id] = writer.register_schema(record.name, record.encoding, record.data)
            names[record.id] = record.name
        elif isinstance(record, Channel) and record.id not in channels:
            schema_id = schemas.get(record.schema_id, 0)
            channel_id = writer.register_channel(record.topic, record.message_encoding, schema_id, record.metadata)
            channels[record.id] = (channel_id, record.topic)
            result.topics.setdefault(
                record.topic,
                TopicStats(names.get(record.schema_id, ""), record.metadata.get("offered_qos_profiles", "")),
            )
        elif isinstance(record, Message) and record.channel_id in channels:
            channel_id, topic = channels[record.channel_id]
            writer.add_message(channel_id, record.log_time, record.data, record.publish_time, record.sequence)
            result.topics[topic].count += 1
            result.start_ns = min(result.start_ns or record.log_time, record.log_time)
            result.end_ns = max(result.end_ns, record.log_time)
        elif isinstance(record, Attachment):
            writer.add_attachment(record.create_time, record.log_time, record.name, record.media_type, record.data)
        elif isinstance(record, Metadata):
            writer.add_metadata(record.name, record.metadata)


def _recover_bag(source: pathlib.Path, target: pathlib.Path) -> list[RecoveredFile]:
    files = sorted(source.glob(f"*{MCAP_SUFFIX}"))
    if not files:
        raise SettingsError(f"{source} holds no {MCAP_SUFFIX} file")
    target.mkdir(parents=True)
    stats, results = BagStats(), []
    for index, path in enumerate(files):
        name = f"{target.name}_{index}{MCAP_SUFFIX}"
        result = recover_file(path, target / name)
        results.append(result)
        stats.files.append(FileStats(name, result.start_ns, result.end_ns, result.messages))
        for topic, found in result.topics.items():
            stats.topics.setdefault(topic, TopicStats(found.message_type, found.offered_qos)).count += found.count
    write_metadata(target, stats)
    return results


def describe(results: list[RecoveredFile], target: pathlib.Path) -> str:
    """One line: what was recovered into `target`, and which files had been cut."""
    cut = [result for result in results if not result.complete]
    counts = ", ".join(f"{topic}: {count}" for topic, count in sorted(_topic_counts(results).items()))
    state = f"{len(cut)} of {len(results)} files had been cut" if cut else "no file had been cut"
    return f"recovered {sum(r.messages for r in results)} messages into {target} ({counts}); {state}"


def _topic_counts(results: list[RecoveredFile]) -> dict[str, int]:
    counts: dict[str, int] = {}
    for result in results:
        for topic, found in result.topics.items():
            counts[topic] = counts.get(topic, 0) + found.count
    return counts
