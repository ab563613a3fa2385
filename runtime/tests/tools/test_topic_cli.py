"""`joshua-topic` against real nodes: list, info, echo, hz and pub over DDS, the domain taken from a build."""

import re
import subprocess
import sys
import time

import pytest
from sensor_msgs.msg import JointState

from testsupport.compiled_settings import compiled_node
from testsupport.joshuac_cli import joshuac
from testsupport.topic_cli import CLI_TIMEOUT_S, topic_cli

TOPIC = "/leader/joint_states"
RECEIVE_TIMEOUT_S = 15.0
LATE_PUBLISHER_S = 3.0  # longer than `--timeout 0` would last if it meant "do not wait"
RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}


@pytest.fixture
def arm(start_node):
    """A mock arm publishing joint states at 20 Hz."""
    return start_node(compiled_node(f'name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "{TOPIC}" rate_hz: 20'))


def test_list_info_echo_and_hz_see_a_running_node(ros_env, arm):
    echoed = topic_cli(ros_env, "echo", TOPIC, "--once", "--timeout", 30)
    assert echoed.returncode == 0, echoed.stderr
    assert re.search(r"^name:\n- \w+", echoed.stdout, re.MULTILINE) and re.search(
        r"^position:\n- -?\d", echoed.stdout, re.MULTILINE
    )
    assert echoed.stdout.count("\n---\n") == 1

    listed = topic_cli(ros_env, "list", "-t", "--wait", 5)
    assert f"{TOPIC} [sensor_msgs/msg/JointState]" in listed.stdout.splitlines()

    info = topic_cli(ros_env, "info", TOPIC)
    assert info.returncode == 0, info.stderr
    assert "Type: sensor_msgs/msg/JointState" in info.stdout and "Publisher count: 1" in info.stdout
    assert "Node name: leader" in info.stdout and "Reliability: " in info.stdout

    hz = topic_cli(ros_env, "hz", TOPIC, "--duration", 3)
    rates = [float(rate) for rate in re.findall(r"average rate: ([\d.]+)", hz.stdout)]
    assert hz.returncode == 0 and rates, hz.stdout + hz.stderr
    assert 5.0 < rates[-1] < 40.0  # 20 Hz asked; a loaded machine only spreads it


def test_pub_sends_nested_messages_a_subscriber_receives(ros_env, ros_client):
    from tf2_msgs.msg import TFMessage

    ros_client.listen("/tf", TFMessage, RELIABLE)
    publisher = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "joshua_runtime.tools.topic_cli",
            "pub",
            "/tf",
            "tf2_msgs/msg/TFMessage",
            "{transforms: [{header: {frame_id: base_link}, child_frame_id: gripper, transform: {translation: {x: 0.5}}}]}",
            "--rate",
            "10",
        ],
        env=ros_env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        arrived = ros_client.spin_until(lambda: ros_client.last("/tf") is not None, RECEIVE_TIMEOUT_S)
    finally:
        publisher.kill()
        _, stderr = publisher.communicate()
    assert arrived, stderr
    [transform] = ros_client.last("/tf").transforms
    assert (transform.header.frame_id, transform.child_frame_id, transform.transform.translation.x) == (
        "base_link",
        "gripper",
        0.5,
    )


def test_the_robot_option_takes_the_domain_from_the_build(ros_env, ros_client, tmp_path):
    description = tmp_path / "r.pbtxt"
    description.write_text(
        f'robot_config {{ name: "r" mode: MODE_TELEOPERATION ros_domain_id: {ros_env["ROS_DOMAIN_ID"]}\n'
        f'  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "{TOPIC}" }} }}\n'
    )
    assert joshuac("build", description, "-o", tmp_path / "out").returncode == 0
    ros_client.listen("/joints_in", JointState, RELIABLE)
    elsewhere = dict(ros_env, ROS_DOMAIN_ID=str(int(ros_env["ROS_DOMAIN_ID"]) + 1))
    sent = topic_cli(
        elsewhere,
        "--robot",
        tmp_path / "out",
        "pub",
        "/joints_in",
        "sensor_msgs/msg/JointState",
        "{name: [shoulder_pan], position: [1.5]}",
        "--times",
        10,
        "--rate",
        10,
        "--wait-matching",
        20,
    )
    assert sent.returncode == 0, sent.stderr
    assert ros_client.spin_until(lambda: ros_client.last("/joints_in") is not None, RECEIVE_TIMEOUT_S)
    assert list(ros_client.last("/joints_in").position) == [1.5]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("pub", "/x", "std_msgs/msg/Strin", "{data: a}"), "message type 'std_msgs/msg/Strin' is not available"),
        (("pub", "/x", "std_msgs/msg/String", "{dat: a}"), "String.dat: no such field (fields: data)"),
        (("pub", "/x", "std_msgs/msg/Int32", "{data: [1}"), "the values are not YAML"),
        (("--robot", "/nonexistent/out", "list"), "/nonexistent/out: no manifest.json"),
        (("echo", "/x", "--timeout", "-1"), "--timeout must be 0 (wait forever) or more"),
    ],
)
def test_bad_input_is_one_line_and_exit_code_2(ros_env, args, message):
    result = topic_cli(ros_env, *args, *(["--once"] if args[0] == "pub" else []))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr


def test_echo_of_a_topic_nobody_publishes_ends_with_a_clear_message(ros_env):
    result = topic_cli(ros_env, "echo", "/nobody", "--timeout", 0.5)
    assert result.returncode == 1
    assert "topic /nobody does not appear in ROS domain" in result.stderr


LATCHED = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}


def test_echo_without_a_message_ends_after_its_default_timeout_with_exit_code_3(ros_env, ros_client):
    from std_msgs.msg import String

    ros_client.publisher("/silent", String, RELIABLE)  # announced, never published
    result = topic_cli(ros_env, "echo", "/silent", "--once")
    assert result.returncode == 3, result.stderr
    assert result.stderr.count("\n") == 1 and result.stdout == ""
    assert result.stderr.startswith("joshua-topic: no message on /silent within 10 s from its publishers (test_client)")
    assert "subscribed RELIABLE, VOLATILE" in result.stderr


def test_echo_of_a_topic_with_subscribers_only_says_it_has_no_publisher(ros_env, ros_client):
    from std_msgs.msg import String

    ros_client.listen("/unfed", String, RELIABLE)
    result = topic_cli(ros_env, "echo", "/unfed", "--timeout", 3)
    assert result.returncode == 1
    assert "topic /unfed has no publisher in ROS domain" in result.stderr and "(only 1 subscription)" in result.stderr


def test_echo_with_timeout_0_waits_for_a_publisher_that_comes_later(ros_env, ros_client):
    from std_msgs.msg import String

    echo = subprocess.Popen(
        [sys.executable, "-m", "joshua_runtime.tools.topic_cli", "echo", "/later", "--once", "--timeout", "0"],
        env=ros_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        time.sleep(LATE_PUBLISHER_S)
        ros_client.publisher("/later", String, LATCHED).publish(String(data="at last"))
        stdout, stderr = echo.communicate(timeout=CLI_TIMEOUT_S)
    finally:
        echo.kill()
    assert echo.returncode == 0, stderr
    assert stdout == "data: at last\n---\n"


def test_echo_hears_every_publisher_that_keeps_a_message_for_late_subscribers(ros_env, ros_client):
    from std_msgs.msg import String

    for name in ("first", "second"):
        ros_client.publisher("/kept", String, LATCHED).publish(String(data=name))
    result = topic_cli(ros_env, "echo", "/kept", "--count", 2)
    assert result.returncode == 0, result.stderr
    assert sorted(result.stdout.split("\n---\n")) == ["", "data: first", "data: second"]
    info = topic_cli(ros_env, "info", "/kept", "--verbose")
    assert info.returncode == 0, info.stderr
    assert "Publisher count: 2" in info.stdout and info.stdout.count("Durability: TRANSIENT_LOCAL") == 2
    assert re.search(r"^GID: [0-9a-f]{2}(\.[0-9a-f]{2})+$", info.stdout, re.M)
    assert "echo and hz subscribe with: RELIABLE, TRANSIENT_LOCAL, depth 10" in info.stdout
