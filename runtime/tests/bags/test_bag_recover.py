"""`joshua-topic bag-recover`: a bag cut by SIGKILL opens with the default (seeking) reader once recovered.

The recorder is SIGKILLed mid-bag; before recovery, mcap's `make_reader` cannot read its last file
(no summary), only `NonSeekingReader` can. After `joshua-topic bag-recover BAG OUT`, every file of OUT
opens with `make_reader`, holds a summary whose statistics agree, and yields exactly the messages
(topic, times, bytes) that NonSeekingReader read from the cut file, decodable with their schemas.
"""

import signal
import subprocess
import sys

import pytest
import yaml
from bag_support import ARM, FOLLOWER, two_arm_recorder
from mcap.exceptions import EndOfFile, McapError
from mcap.reader import NonSeekingReader, make_reader
from mcap_ros2.decoder import DecoderFactory

pytestmark = pytest.mark.process

SPLIT_S = 2
WAIT_S = 20.0
TOPIC_CLI = [sys.executable, "-m", "joshua_runtime.tools.topic_cli"]


def streamed(path) -> list[tuple]:
    """(topic, log time, publish time, data) of every message NonSeekingReader reads before the cut."""
    found = []
    with open(path, "rb") as stream:
        try:
            for _, channel, message in NonSeekingReader(stream).iter_messages(log_time_order=False):
                found.append((channel.topic, message.log_time, message.publish_time, message.data))
        except EndOfFile:
            pass
    return found


def seeked(path) -> list[tuple]:
    """The same through make_reader, which seeks to the summary; its statistics must agree."""
    with open(path, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None, path
        found = [
            (channel.topic, message.log_time, message.publish_time, message.data)
            for _, channel, message in reader.iter_messages(log_time_order=False)
        ]
        assert summary.statistics.message_count == len(found)
        for _, _, _, decoded in reader.iter_decoded_messages(log_time_order=False):
            assert list(decoded.name)  # JointState, decoded with the recovered schema
        return found


def seekable(path) -> bool:
    try:
        seeked(path)
        return True
    except (McapError, AssertionError, ValueError):
        return False


def recover(*paths) -> subprocess.CompletedProcess:
    return subprocess.run([*TOPIC_CLI, "bag-recover", *map(str, paths)], capture_output=True, text=True, check=False)


@pytest.fixture
def cut_bag(start_node, ros_client, tmp_path):
    """A bag directory of 2 s files whose recorder was SIGKILLed once its second file had a finished chunk."""
    settings = two_arm_recorder(tmp_path / "bags", f"bag_max_duration_s: {SPLIT_S}")
    start_node(settings["arm"])
    start_node(settings["follower"])
    recorder = start_node(settings["recorder"])
    node = ros_client.node
    assert ros_client.spin_until(lambda: node.count_subscribers(FOLLOWER) > 0, WAIT_S), recorder.failure()
    [bag] = (tmp_path / "bags").iterdir()

    def second_file_has_a_chunk() -> bool:
        files = sorted(bag.glob("*.mcap"))
        return len(files) >= 2 and bool(streamed(files[-1]))

    assert ros_client.spin_until(second_file_has_a_chunk, WAIT_S), recorder.failure()
    assert recorder.stop(signal.SIGKILL)[0] == -signal.SIGKILL  # well before the next split
    return bag


def test_a_bag_cut_by_sigkill_opens_with_the_seeking_reader_once_recovered(cut_bag, tmp_path):
    files = sorted(cut_bag.glob("*.mcap"))
    assert len(files) >= 2
    assert not seekable(files[-1])  # the file the kill cut: no summary to seek to
    before = [streamed(path) for path in files]

    out = tmp_path / "recovered"
    result = recover(cut_bag, out)
    assert result.returncode == 0, result.stderr
    total = sum(map(len, before))
    assert result.stdout.startswith(f"recovered {total} messages into {out} ({ARM}: ")
    assert result.stdout.endswith(f"; 1 of {len(files)} files had been cut\n")

    recovered = sorted(out.glob("*.mcap"))
    assert [path.name for path in recovered] == [f"recovered_{index}.mcap" for index in range(len(files))]
    assert [seeked(path) for path in recovered] == before
    metadata = yaml.safe_load((out / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert metadata["message_count"] == total
    assert [entry["message_count"] for entry in metadata["files"]] == list(map(len, before))
    counts = {
        entry["topic_metadata"]["name"]: entry["message_count"] for entry in metadata["topics_with_message_count"]
    }
    assert counts == {topic: sum(m[0] == topic for f in before for m in f) for topic in counts}
    assert set(counts) == {ARM, FOLLOWER}

    single = tmp_path / "last.mcap"
    result = recover(files[-1], single)
    assert result.returncode == 0, result.stderr
    assert seeked(single) == before[-1]
    assert not seekable(files[-1])  # IN is left as it was


def test_bad_paths_are_refused_in_one_line(tmp_path):
    existing = tmp_path / "out"
    existing.mkdir()
    (tmp_path / "bag").mkdir()
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not an mcap file at all")
    cases = [
        (
            (tmp_path / "missing", tmp_path / "new"),
            2,
            f"{tmp_path / 'missing'} is neither an MCAP file nor a bag directory",
        ),
        ((tmp_path / "bag", existing), 2, f"{existing} exists; choose a new name for the recovered bag"),
        ((tmp_path / "bag", tmp_path / "new"), 2, f"{tmp_path / 'bag'} holds no .mcap file"),
        ((junk, tmp_path / "new.mcap"), 1, f"{junk} is not an MCAP file"),
    ]
    for paths, code, message in cases:
        result = recover(*paths)
        assert result.returncode == code, (paths, result.stderr)
        assert result.stderr.startswith(f"joshua-topic: {message}") and result.stderr.count("\n") == 1, result.stderr
    assert not (tmp_path / "new").exists() and not (tmp_path / "new.mcap").exists()
