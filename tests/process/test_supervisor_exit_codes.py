"""Exit codes tell the truth: a node that lost data makes the supervisor fail and say so last; a node
whose settings are unusable (exit code 2) is failed at once, never restarted."""

import fcntl
import os
import re
import signal
import struct
from contextlib import contextmanager
from pathlib import Path

from supervisor_harness import Supervisor, build, robot, wait_until

from joshua_codegen.supervisor.policy import EXIT_CRITICAL, EXIT_DATA_LOST
from joshua_core.exit_codes import NODE_EXIT_DATA_LOST, NODE_EXIT_SETTINGS

OFFLINE = {"HF_HUB_OFFLINE": "1", "HF_DATASETS_OFFLINE": "1", "TRANSFORMERS_OFFLINE": "1"}
RECORDER_START_S = 120.0  # importing LeRobot and torch on a busy machine
# linux/fs.h: the inode flags ioctls and the immutable flag (no entry of the directory may be added,
# removed or renamed, by root neither)
FS_IOC_GETFLAGS, FS_IOC_SETFLAGS, FS_IMMUTABLE_FL = 0x80086601, 0x40086602, 0x10


@contextmanager
def immutable(directory: Path):
    fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    try:
        flags = struct.unpack("l", fcntl.ioctl(fd, FS_IOC_GETFLAGS, struct.pack("l", 0)))[0]
        fcntl.ioctl(fd, FS_IOC_SETFLAGS, struct.pack("l", flags | FS_IMMUTABLE_FL))
        try:
            yield
        finally:
            fcntl.ioctl(fd, FS_IOC_SETFLAGS, struct.pack("l", flags))
    finally:
        os.close(fd)


def test_unusable_settings_fail_the_node_at_once_without_restarts(tmp_path):
    arm = 'node { name: "arm" type: MOCK_ENCODER_PUBLISHER restart: RESTART_ALWAYS max_restarts: 5 }'
    out = build(tmp_path, robot([arm]))
    entrypoint = out / "nodes" / "arm.py"
    entrypoint.write_text(entrypoint.read_text().replace("'MOCK_ENCODER_PUBLISHER'", "'NO_SUCH_TYPE'"))
    supervisor = Supervisor(out)
    try:
        assert supervisor.wait(timeout=30) == EXIT_CRITICAL
    finally:
        supervisor.close()
    log = supervisor.log()
    assert "arm: error: no runtime implementation for node type 'NO_SUCH_TYPE'" in log
    assert f"arm: exited with code {NODE_EXIT_SETTINGS}: its settings are unusable" in log
    assert "restarting in" not in log and len(re.findall(r"arm: started pid", log)) == 1


def test_a_recorder_that_cannot_save_its_episode_makes_the_supervisor_fail_and_say_so_last(tmp_path, ros_env):
    parent = tmp_path / "data"
    parent.mkdir()
    dataset = parent / "dataset"
    out = build(
        tmp_path,
        robot(
            [
                'node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/arm/joint_states" rate_hz: 30 }',
                (
                    f'node {{ name: "recorder" type: DATA_SUBSCRIBER topic_name: "/arm/joint_states" output_format: "parquet" '
                    'input_topics: ["/arm/joint_states"] '
                    f'output_directory: "{dataset}" rate_hz: 10 restart: RESTART_NEVER }}'
                ),
            ],
            sigint=30,
            sigterm=5,
        ),
    )
    env = dict(ros_env, **OFFLINE, HF_DATASETS_CACHE=str(tmp_path / "hf-cache"), HF_LEROBOT_HOME=str(tmp_path / "hf"))
    supervisor = Supervisor(out, env=env)
    try:
        supervisor.wait_log(r"recorder.*first frame of the episode recorded", timeout=RECORDER_START_S)
        # The staging copy is made by the dataset writer, which records only once it has loaded LeRobot.
        wait_until(lambda: (parent / "dataset.staging").is_dir(), "the episode's staging copy", RECORDER_START_S)
        with immutable(parent):  # the saved episode cannot be swapped in: the kernel refuses, root or not
            supervisor.signal(signal.SIGINT)
            code = supervisor.wait(timeout=60)
    finally:
        supervisor.close()
    log = supervisor.log()
    assert code == EXIT_DATA_LOST, log
    assert re.search(rf"recorder: pid \d+ exited with code {NODE_EXIT_DATA_LOST}", log)
    assert re.search(rf"recorder: error.*episode of \d+ frames lost, not saved to {dataset}", log)
    assert (
        log.rstrip()
        .splitlines()[-1]
        .endswith(
            f"supervisor: data lost: node recorder could not save data it had taken in to {dataset} "
            f"(exit code {NODE_EXIT_DATA_LOST}; its error line above says what)"
        )
    )
    assert not dataset.exists()
