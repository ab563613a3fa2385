"""DATA_SUBSCRIBER with output_format "mcap" records a rosbag2 MCAP bag, read back with mcap's own reader."""

import signal
import time

import yaml
from mcap.exceptions import EndOfFile
from mcap.reader import NonSeekingReader, make_reader
from mcap_ros2.decoder import DecoderFactory
from sensor_msgs.msg import JointState

from testsupport.compiled_settings import compiled_settings

ARM = "/arm/joint_states"
OUTSIDE = "/outside/tf"
RECORD_S = 3.5
WAIT_S = 20.0
RELIABLE = {"history": "KEEP_LAST", "depth": 100, "reliability": "RELIABLE", "durability": "VOLATILE"}


def description(out, extra=""):
    return compiled_settings(f'''robot_config {{
      name: "bagbot" mode: MODE_DATA_COLLECTION
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 50 }}
      node {{ name: "recorder" type: DATA_SUBSCRIBER topic_name: "{ARM}" input_topics: ["{OUTSIDE}"]
              output_format: "mcap" output_directory: "{out}" {extra} }}
    }}''')


def record(start_node, ros_client, settings, seconds):
    """Run the arm and the recorder while this process publishes numbered transforms on OUTSIDE.

    Returns (recorder process, transforms published, joint states heard here)."""
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    ros_client.listen(ARM, JointState, RELIABLE, keep=1000)
    publisher = ros_client.publisher(OUTSIDE, TFMessage, RELIABLE)
    sent = []

    def publish_next():
        transform = TransformStamped(child_frame_id=f"frame_{len(sent)}")
        transform.transform.translation.x = float(len(sent))
        sent.append(TFMessage(transforms=[transform]))
        publisher.publish(sent[-1])

    publish_next()  # the recorder learns OUTSIDE's type from this publisher
    arm = start_node(settings["arm"])
    recorder = start_node(settings["recorder"])
    # The recording's seconds count once the recorder subscribed and the arm publishes (it may start later).
    assert ros_client.spin_until(
        lambda: publisher.get_subscription_count() > 0 and ros_client.count(ARM) > 0, WAIT_S
    ), f"recorder: {recorder.failure()}; arm: {arm.failure()}"
    ticks_until = time.monotonic() + seconds
    while time.monotonic() < ticks_until:
        publish_next()
        ros_client.spin_until(lambda: False, 0.05)
    ros_client.spin_until(lambda: False, 0.3)
    arm.kill()
    return recorder, sent[1:], ros_client.messages(ARM)


def bag_directory(root):
    [bag] = [p for p in root.iterdir() if p.is_dir()]
    assert bag.name.startswith("bagbot_")
    return bag


def decoded(path):
    """(topic, schema name, decoded message) of every message of one MCAP file."""
    with open(path, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        return [
            (channel.topic, schema.name, message)
            for schema, channel, _, message in reader.iter_decoded_messages(log_time_order=False)
        ]


def test_a_bag_holds_every_topic_with_its_definitions_and_splits_by_duration(start_node, ros_client, tmp_path):
    settings = description(tmp_path, "bag_max_duration_s: 1.0")
    recorder, sent, heard = record(start_node, ros_client, settings, RECORD_S)
    code, _, stderr = recorder.stop(signal.SIGINT)
    assert code == 0, stderr
    bag = bag_directory(tmp_path)
    info = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    files = info["relative_file_paths"]
    assert len(files) >= 3 and sorted(p.name for p in bag.glob("*.mcap")) == sorted(files)
    assert info["storage_identifier"] == "mcap"
    records = [record for name in files for record in decoded(bag / name)]
    assert info["message_count"] == len(records) == sum(f["message_count"] for f in info["files"])
    tf_schemas = []
    for name in files:  # a busy machine may deliver the first transform after the first file's second
        with open(bag / name, "rb") as stream:
            reader = make_reader(stream)
            assert reader.get_header().profile == "ros2"
            summary = reader.get_summary()
            assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
            assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
            tf_schemas += [s for s in summary.schemas.values() if s.name == "tf2_msgs/msg/TFMessage"]
    assert tf_schemas and all(b"MSG: geometry_msgs/TransformStamped" in schema.data for schema in tf_schemas)

    recorded_tf = [m for topic, schema, m in records if topic == OUTSIDE]
    assert [t.transforms[0].transform.translation.x for t in recorded_tf] == [
        float(i) for i in range(int(recorded_tf[0].transforms[0].transform.translation.x), len(sent) + 1)
    ]
    assert [t.transforms[0].child_frame_id for t in recorded_tf][-1] == sent[-1].transforms[0].child_frame_id
    recorded_arm = {
        (m.header.stamp.sec, m.header.stamp.nanosec): list(m.position) for topic, schema, m in records if topic == ARM
    }
    assert all(schema == "sensor_msgs/msg/JointState" for topic, schema, _ in records if topic == ARM)
    # The arm is killed at the end: what it sent last can reach this process and not the recorder (a reliable
    # writer's resends end with it), so the comparison ends at the recorder's last message.
    first, last = min(recorded_arm), max(recorded_arm)
    while_recording = [m for m in heard if first <= (m.header.stamp.sec, m.header.stamp.nanosec) <= last]
    assert len(while_recording) > 50
    for message in while_recording:  # the recorder heard what this process heard, and stored it unchanged
        assert recorded_arm[(message.header.stamp.sec, message.header.stamp.nanosec)] == list(message.position)


def test_a_killed_recorder_leaves_a_bag_readable_up_to_its_last_chunk(start_node, ros_client, tmp_path):
    recorder, sent, _ = record(start_node, ros_client, description(tmp_path), RECORD_S)
    recorder.stop(signal.SIGKILL)
    [path] = bag_directory(tmp_path).glob("*.mcap")
    with open(path, "rb") as stream:
        reader = NonSeekingReader(stream, decoder_factories=[DecoderFactory()])
        recovered = []
        try:
            for _, channel, _, message in reader.iter_decoded_messages(log_time_order=False):
                if channel.topic == OUTSIDE:
                    recovered.append(message.transforms[0].transform.translation.x)
        except EndOfFile:  # the unfinished tail of the file
            pass
    assert len(recovered) >= len(sent) - 40  # at most about one chunk period (1 s at 20 Hz) lost
    assert recovered == sorted(recovered)


def test_a_restart_within_the_same_second_gets_a_bag_of_its_own(tmp_path):
    from joshua_runtime.bags.bag_recorder_node import new_bag_directory

    first = new_bag_directory(tmp_path, "bagbot")
    first.mkdir()
    second = new_bag_directory(tmp_path, "bagbot")
    assert second != first and second.name.startswith(first.name[: len("bagbot_")])
