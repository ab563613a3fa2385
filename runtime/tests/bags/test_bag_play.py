"""`joshua-topic play` publishes a bag the project's recorder wrote, with its timing and its publishers' QoS.

The bag: a mock arm's joint states (reliable, volatile) and a latched std_msgs/String this test
publishes (transient local, depth 1), recorded by a DATA_SUBSCRIBER with output_format mcap. rclpy
subscribers in this process then receive the played messages: the same ones in the same order, published
with the recorded gaps divided by --rate; the latched string reaches a subscriber that joins long after it
was published. Timing is read from each sample's source timestamp (when the player wrote it), so that how
late this busy process takes its messages does not count.
"""

import signal
import subprocess
import sys
import time

import pytest
from bag_support import ARM
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_runtime.bags.bag_reader import open_bag
from testsupport.compiled_settings import compiled_settings
from testsupport.topic_cli import topic_cli

LATCHED = "/play/latched"
RECORD_S = 2.0
WAIT_S = 20.0
PLAY_TIMEOUT_S = 60.0
PUBLISHERS_FIRST_S = 3.0
RELIABLE = {"history": "KEEP_LAST", "depth": 1000, "reliability": "RELIABLE", "durability": "VOLATILE"}
LATCHED_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
# How far the slope of the played publication times over the recorded times divided by --rate (least squares
# over every message) may stray from 1. A player that ignored the rate gives 2, one that ignored the timing
# about 0; a message the busy machine holds back by D seconds moves the slope by at most 0.15 * D (40 messages
# over one second), and each is late on its own: the player waits for absolute deadlines.
SLOPE_TOLERANCE = 0.2
# The looping play of the latched test: slow, so that the reader that joins after "second" was published
# matches long before the next loop publishes it again (each loop is the bag's 2 s divided by this).
LOOP_RATE = 0.5


def record_bag(start_node, ros_client, output):
    settings = compiled_settings(f'''robot_config {{
      name: "playbot" mode: MODE_DATA_COLLECTION
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 20 }}
      node {{ name: "recorder" type: DATA_SUBSCRIBER topic_name: "{ARM}" input_topics: ["{LATCHED}"]
              output_format: "mcap" output_directory: "{output}" }}
    }}''')
    latched = ros_client.publisher(LATCHED, String, LATCHED_QOS)
    latched.publish(String(data="first"))  # the recorder learns the type from this publisher
    arm = start_node(settings["arm"])
    recorder = start_node(settings["recorder"])
    assert ros_client.spin_until(lambda: latched.get_subscription_count() > 0, WAIT_S), recorder.failure()
    # The recording window starts once the arm publishes and the recorder's subscription to it is known: a
    # busy machine took longer than the window to start the arm node.
    ros_client.listen(ARM, JointState, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.count(ARM) > 0, WAIT_S), arm.failure()
    assert ros_client.subscriptions_info(ARM, WAIT_S), recorder.failure()
    ros_client.spin_until(lambda: False, RECORD_S / 2)
    latched.publish(String(data="second"))
    ros_client.spin_until(lambda: False, RECORD_S / 2)
    arm.kill()
    code, _, stderr = recorder.stop(signal.SIGINT)
    assert code == 0, stderr
    ros_client.node.destroy_publisher(latched)  # from now on only the player publishes the latched topic
    [bag] = [p for p in output.iterdir() if p.is_dir()]
    return open_bag(bag)


def sigint_ignored() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def play(env, bag, *options) -> subprocess.Popen:
    """The player, its publishers made PUBLISHERS_FIRST_S before its first message, so this process's graph
    queries and subscriptions find them before a short bag is over. It starts with SIGINT ignored, as a
    shell's background job does (and a test worker's child may): Ctrl-C must stop it all the same."""
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "joshua_runtime.tools.topic_cli",
            "play",
            str(bag.path),
            "--delay",
            str(PUBLISHERS_FIRST_S),
            *options,
        ],  # fmt: skip
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=sigint_ignored,
    )


@pytest.fixture
def players(ros_env):
    """play(ros_env, ...) for the test; a player still running when the test ends (it failed) is killed, so
    that no looping player outlives its test in a ROS domain a later test takes."""
    started = []

    def start(bag, *options) -> subprocess.Popen:
        started.append(play(ros_env, bag, *options))
        return started[-1]

    yield start
    for player in started:
        if player.poll() is None:
            player.kill()
        player.communicate(timeout=PLAY_TIMEOUT_S)


def finished(process: subprocess.Popen, ros_client) -> str:
    """What the player printed, once it ended (while this process receives what it publishes)."""
    ros_client.spin_until(lambda: process.poll() is not None, PLAY_TIMEOUT_S)
    stdout, stderr = process.communicate(timeout=PLAY_TIMEOUT_S)
    assert process.returncode == 0, stderr
    return stdout


def stamps(messages) -> list[int]:
    return [m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec for m in messages]


def missing(bag, played) -> list[int]:
    """The positions in the bag of the arm messages that `played` lacks (told apart by their header stamps)."""
    got = set(stamps(played))
    recorded = stamps([deserialize_message(data, JointState) for _, data, _ in bag.messages([ARM])])
    return [i for i, stamp in enumerate(recorded) if stamp not in got]


def slope(played_ns: list[int], recorded_ns: list[int], rate: float) -> float:
    """Least-squares slope of the played times over the recorded times divided by `rate` (1 when kept)."""
    expected = [(t - recorded_ns[0]) / rate for t in recorded_ns]
    played = [t - played_ns[0] for t in played_ns]
    mean_expected, mean_played = sum(expected) / len(expected), sum(played) / len(played)
    covariance = sum((e - mean_expected) * (p - mean_played) for e, p in zip(expected, played, strict=True))
    return covariance / sum((e - mean_expected) ** 2 for e in expected)


def test_play_keeps_the_timing_divided_by_rate_and_the_latched_topics_latched(
    start_node, ros_client, players, tmp_path
):
    bag = record_bag(start_node, ros_client, tmp_path / "bags")
    recorded = [log_time for _, _, log_time in bag.messages([ARM])]
    assert len(recorded) >= 10 and bag.topics[LATCHED].count == 1  # "first" came before the recorder

    ros_client.listen(ARM, JointState, RELIABLE, keep=1000)
    published_ns = []  # each played arm message's source timestamp: when the player wrote it
    ros_client.node.create_subscription(
        JointState, ARM, lambda _m, info: published_ns.append(info["source_timestamp"]), 1000
    )
    player = players(bag, "--rate", "2")
    [publisher] = ros_client.publishers_info(ARM, WAIT_S)
    assert publisher.qos_profile.reliability == ReliabilityPolicy.RELIABLE
    assert publisher.qos_profile.durability == DurabilityPolicy.VOLATILE
    output = finished(player, ros_client)
    ros_client.spin_until(lambda: ros_client.count(ARM) == len(recorded), WAIT_S)
    assert output.endswith(f"published {len(recorded) + 1} messages\n"), output
    played = ros_client.messages(ARM)
    assert len(played) == len(recorded) == len(published_ns), (len(published_ns), missing(bag, played))
    assert stamps(played) == sorted(stamps(played))
    kept = slope(published_ns, recorded, 2)
    assert abs(kept - 1) <= SLOPE_TOLERANCE, (kept, published_ns, recorded)

    # The latched string, once a first reader has seen it published, reaches a reader that joins later: the
    # sample it gets was written before it joined (the publisher's history, not a new publication).
    ros_client.listen(LATCHED, String, LATCHED_QOS, keep=10)
    looping = players(bag, "--loop", "--rate", str(LOOP_RATE))
    [latched] = ros_client.publishers_info(LATCHED, WAIT_S)
    assert latched.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert ros_client.spin_until(lambda: ros_client.count(LATCHED) >= 1, WAIT_S + PUBLISHERS_FIRST_S)
    joined_ns = time.time_ns()
    late = []
    ros_client.node.create_subscription(
        String, LATCHED, lambda message, info: late.append((message.data, info["source_timestamp"])), LATCHED_QOS
    )
    assert ros_client.spin_until(lambda: late, WAIT_S)
    looping.send_signal(signal.SIGINT)
    assert finished(looping, ros_client).startswith("playing ")
    assert late[0][0] == "second"
    assert late[0][1] < joined_ns, (late, joined_ns)


def test_play_chooses_topics_and_a_start_and_loops_until_stopped(start_node, ros_client, players, tmp_path):
    bag = record_bag(start_node, ros_client, tmp_path / "bags")
    start_s = 1.0
    after_start = [t for _, _, t in bag.messages([ARM], bag.start_ns + round(start_s * 1e9))]
    assert 0 < len(after_start) < bag.topics[ARM].count

    ros_client.listen(ARM, JointState, RELIABLE, keep=1000)
    output = finished(players(bag, "--topics", ARM, "--start", str(start_s), "--rate", "4"), ros_client)
    assert output.endswith(f"published {len(after_start)} messages\n"), output
    assert ros_client.spin_until(lambda: ros_client.count(ARM) == len(after_start), WAIT_S)
    assert not ros_client.publishers_info(LATCHED, 0.5)  # not chosen: never published

    ros_client.listen(ARM, JointState, RELIABLE, keep=1000)
    looping = players(bag, "--topics", ARM, "--loop", "--rate", "4")
    assert ros_client.spin_until(lambda: ros_client.count(ARM) > 2 * bag.topics[ARM].count, PLAY_TIMEOUT_S)
    looping.send_signal(signal.SIGINT)
    assert finished(looping, ros_client).startswith("playing ")


def test_play_refuses_what_it_cannot_play_in_one_line(ros_env, tmp_path):
    missing = topic_cli(ros_env, "play", tmp_path / "nothing")
    assert missing.returncode == 2
    assert (
        missing.stderr == f"joshua-topic: {tmp_path / 'nothing'}: no such bag (give a bag directory or an .mcap file)\n"
    )
    rate = topic_cli(ros_env, "play", tmp_path, "--rate", "0")
    assert (rate.returncode, rate.stderr) == (2, "joshua-topic: --rate must be above 0\n")
