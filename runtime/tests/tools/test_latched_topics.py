"""`joshua-topic` started after the robot gets the messages its publishers keep for late subscribers.

The robot (testsupport/latched_robot.py) is a generated one run by its supervisor. Whether a late
reader discovers a subscription of the topic before its publisher is a race, so the test repeats the
late reader.
"""

import re
import subprocess

import pytest

from testsupport.foxglove_client import free_port
from testsupport.latched_robot import latched_robot
from testsupport.running_robot import running_robot
from testsupport.topic_cli import topic_cli

ROUNDS = 5
ECHO_LIMIT_S = 40.0  # a reader that hangs fails the round (echo's own default timeout is 10 s)


def test_echo_started_after_the_robot_prints_the_latched_messages_every_time(tmp_path, ros_env):
    description = latched_robot(ros_env["ROS_DOMAIN_ID"], tmp_path / "bags", free_port())
    with running_robot(description, tmp_path, ros_env) as out:
        for round_ in range(ROUNDS):
            for topic, printed in (("/tf_static", r"child_frame_id: laser"), ("/robot_description", r"<robot")):
                try:
                    echoed = topic_cli(ros_env, "--robot", out, "echo", topic, "--once", timeout=ECHO_LIMIT_S)
                except subprocess.TimeoutExpired:
                    pytest.fail(f"round {round_ + 1}, {topic}: echo printed nothing and hung for {ECHO_LIMIT_S} s")
                assert echoed.returncode == 0, f"round {round_ + 1}, {topic}: {echoed.stderr}"
                assert re.search(printed, echoed.stdout), f"round {round_ + 1}, {topic}: {echoed.stdout}"
