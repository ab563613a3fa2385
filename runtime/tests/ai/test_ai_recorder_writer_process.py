"""The recorder is ready before LeRobot is loaded: its dataset writer is a process of its own.

The node announces itself ready (READY=1) once subscribed and records at once; the writer process
imports LeRobot meanwhile and writes the queued frames. These tests check the order of events (never
a duration), that the node itself never loads torch, and how the pair ends: the writer dies with the
node, a writer that dies ends the node with exit 6, a stop before the writer has loaded waits for it
when frames were recorded (they are saved) and is prompt when none were.
"""

import os
import re
import signal
import time
from pathlib import Path

from ai_support import RELIABLE, NodeProcess, slow_lerobot_env
from std_msgs.msg import String
from test_ai_recorder import Sensors, load, record_one, recorder_settings, send

READY = r"ready: recording 3 topics"
WRITER_READY = r"dataset writer ready [\d.]+ s after the start"
GONE_TIMEOUT_S = 30.0  # only ends a wait for a process that never goes
SLOW_LEROBOT_S = 8.0
NEVER_S = 600.0


def children(pid: int) -> list[int]:
    found = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        found += [int(child) for child in (task / "children").read_text().split()]
    return found


def wait_until_gone(pid: int) -> bool:
    deadline = time.monotonic() + GONE_TIMEOUT_S
    while time.monotonic() < deadline:
        try:
            if Path(f"/proc/{pid}/stat").read_text().split(") ")[1].startswith("Z"):
                return True  # a zombie: it has exited
        except FileNotFoundError:
            return True
        time.sleep(0.05)
    return False


def line_index(node, pattern: str) -> int:
    node.wait_for(pattern)
    return next(i for i, line in enumerate(node.lines) if re.search(pattern, line))


def test_the_node_is_ready_before_its_writer_has_loaded_lerobot_and_never_loads_torch(
    tmp_path, ai_env, ros_peer, lerobot_offline
):
    output = tmp_path / "dataset"
    Sensors(ros_peer)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)
    try:
        assert line_index(node, READY) < line_index(node, WRITER_READY), node.output
        (writer,) = children(node.process.pid)
        node_libraries = Path(f"/proc/{node.process.pid}/maps").read_text()
        writer_libraries = Path(f"/proc/{writer}/maps").read_text()
        assert "libtorch" in writer_libraries
        assert "libtorch" not in node_libraries  # the node's ROS thread never shares the GIL with an import
        record_one(node, 0)
        assert node.stop(signal.SIGINT) == 0
        frames = int(node.wait_for(r"episode 0 saved: (\d+) frames").group(1))
    finally:
        node.kill()
    assert wait_until_gone(writer)
    assert len(load(output)) == frames > 0


def test_the_writer_process_dies_with_the_node(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    Sensors(ros_peer)
    commands = ros_peer.publisher("/ai_recorder/episode", String, RELIABLE)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)
    try:
        node.wait_for(WRITER_READY)
        record_one(node, 0)
        mark = node.count()
        send(ros_peer, commands, "stop")
        saved = int(node.wait_for(r"episode 0 saved: (\d+) frames", after=mark).group(1))
        send(ros_peer, commands, "start")
        record_one(node, mark)
        (writer,) = children(node.process.pid)
        node.process.kill()
        node.process.wait()
    finally:
        node.kill()
    assert wait_until_gone(writer), "the writer process outlived its node"
    assert len(load(output)) == saved  # the episode in progress is lost, the saved one is intact


def test_a_writer_process_that_dies_ends_the_node_with_exit_6(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    Sensors(ros_peer)
    node = NodeProcess(recorder_settings(output, "parquet"), ai_env)
    try:
        node.wait_for(WRITER_READY)
        record_one(node, 0)
        (writer,) = children(node.process.pid)
        os.kill(writer, signal.SIGKILL)
        code = node.process.wait(GONE_TIMEOUT_S)
    finally:
        node.kill()
    assert code == 6, node.output
    errors = [line for line in node.lines if line.startswith("ai_recorder: error")]
    assert len(errors) == 1, node.output
    assert "the dataset writer process ended unexpectedly (exit code -9)" in errors[0]
    assert "frames in progress is lost" in errors[0]


def test_a_stop_before_the_writer_has_loaded_lerobot_saves_the_frames_recorded_meanwhile(
    tmp_path, ai_env, ros_peer, lerobot_offline
):
    env = slow_lerobot_env(tmp_path, ai_env, SLOW_LEROBOT_S)
    output = tmp_path / "dataset"
    Sensors(ros_peer)
    node = NodeProcess(recorder_settings(output, "parquet"), env)
    try:
        record_one(node, 0)
        assert not [line for line in node.lines if re.search(WRITER_READY, line)]  # still loading
        assert node.stop(signal.SIGINT, timeout=SLOW_LEROBOT_S + GONE_TIMEOUT_S) == 0, node.output
        node.wait_for(r"saving the \d+ frames recorded so far waits for the dataset writer, still loading LeRobot")
        frames = int(node.wait_for(r"episode 0 saved: (\d+) frames").group(1))
    finally:
        node.kill()
    assert len(load(output)) == frames > 0


def test_a_stop_before_the_writer_has_loaded_lerobot_with_no_frame_does_not_wait_for_it(
    tmp_path, ai_env, lerobot_offline
):
    env = slow_lerobot_env(tmp_path, ai_env, NEVER_S)
    output = tmp_path / "dataset"
    node = NodeProcess(recorder_settings(output, "parquet"), env)  # nothing publishes: no frame
    try:
        node.wait_for(READY)
        (writer,) = children(node.process.pid)
        assert node.stop(signal.SIGINT, timeout=GONE_TIMEOUT_S) == 0, node.output  # far less than NEVER_S
    finally:
        node.kill()
    assert wait_until_gone(writer)
    assert not output.exists()
