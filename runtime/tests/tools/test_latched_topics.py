"""`joshua-topic` started after the robot gets the messages its publishers keep for late subscribers.

The robot is a generated one run by its supervisor: mock arms, camera and lidar, a ROBOT_STATE_PUBLISHER
(/tf_static and /robot_description, transient local), a recorder and a Foxglove bridge that subscribe
to those topics too. Whether a late reader discovers a subscription of the topic before its publisher
is a race, so the test repeats the late reader.
"""

import re
import socket
import subprocess

import pytest

from testsupport.running_robot import running_robot
from testsupport.topic_cli import topic_cli

ROUNDS = 5
ECHO_LIMIT_S = 40.0  # a reader that hangs fails the round (echo's own default timeout is 10 s)


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def latched_robot(domain: str, bags) -> str:
    return f'''robot_config {{ name: "latched" mode: MODE_TELEOPERATION ros_domain_id: {domain}
      foxglove {{ port: {free_port()} host: "127.0.0.1" }}
      node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 50 }}
      node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states"
              state_topic: "/follower/joint_states" }}
      node {{ name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera/image_raw" width: 320 height: 240 }}
      node {{ name: "lidar" type: MOCK_LIDAR_PUBLISHER topic_name: "/scan" }}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "/follower/joint_states" }}
      node {{ name: "recorder" type: DATA_SUBSCRIBER output_format: "mcap" topic_name: "/follower/joint_states"
              output_directory: "{bags}" input_topics: ["/leader/joint_states", "/scan", "/tf"] }} }}'''


def test_echo_started_after_the_robot_prints_the_latched_messages_every_time(tmp_path, ros_env):
    with running_robot(latched_robot(ros_env["ROS_DOMAIN_ID"], tmp_path / "bags"), tmp_path, ros_env) as out:
        for round_ in range(ROUNDS):
            for topic, printed in (("/tf_static", r"child_frame_id: laser"), ("/robot_description", r"<robot")):
                try:
                    echoed = topic_cli(ros_env, "--robot", out, "echo", topic, "--once", timeout=ECHO_LIMIT_S)
                except subprocess.TimeoutExpired:
                    pytest.fail(f"round {round_ + 1}, {topic}: echo printed nothing and hung for {ECHO_LIMIT_S} s")
                assert echoed.returncode == 0, f"round {round_ + 1}, {topic}: {echoed.stderr}"
                assert re.search(printed, echoed.stdout), f"round {round_ + 1}, {topic}: {echoed.stdout}"
