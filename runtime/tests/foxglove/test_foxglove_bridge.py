"""`foxglove { }` adds a bridge process; a WebSocket client subscribes to channels and decodes messages."""

import asyncio
import json

import pytest
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState

from testsupport.compiled_settings import compiled_settings
from testsupport.foxglove_client import first_messages, free_port
from testsupport.joshuac_cli import joshuac

pytestmark = pytest.mark.process

ARM = "/arm/joint_states"


def description(port: int) -> str:
    return f'''robot_config {{ name: "fx" mode: MODE_TELEOPERATION
      foxglove {{ port: {port} bind: "127.0.0.1" }}
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 20 }}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "{ARM}" }} }}'''


def test_the_build_adds_a_bridge_process_serving_the_described_topics(tmp_path):
    source = tmp_path / "fx.pbtxt"
    source.write_text(description(8765))
    assert joshuac("build", source, "-o", tmp_path / "out").returncode == 0
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert "foxglove_bridge" in [p["name"] for p in manifest["processes"]]
    settings = compiled_settings(description(8765))["foxglove_bridge"]
    assert settings["type"] == "FOXGLOVE_BRIDGE" and settings["foxglove"] == {"port": 8765, "host": "127.0.0.1"}
    # The ROBOT_STATE_PUBLISHER's own topics are described too, the latched ones served transient local.
    assert [(t["name"], t["qos"]["durability"]) for t in settings["inputs"]] == [
        (ARM, "VOLATILE"),
        ("/robot_description", "TRANSIENT_LOCAL"),
        ("/tf", "VOLATILE"),
        ("/tf_static", "TRANSIENT_LOCAL"),
    ]


def test_a_websocket_client_receives_joint_states_and_transforms(start_node, ros_env):
    from tf2_msgs.msg import TFMessage

    port = free_port()
    settings = compiled_settings(description(port))
    for name in ("arm", "state", "foxglove_bridge"):
        start_node(settings[name])
    channels, payloads = asyncio.run(first_messages(port, [ARM, "/tf"]))
    assert channels[ARM]["encoding"] == "cdr" and channels[ARM]["schemaEncoding"] == "ros2msg"
    assert channels[ARM]["schemaName"] == "sensor_msgs/msg/JointState"
    assert "MSG: std_msgs/Header" in channels[ARM]["schema"]
    joints = deserialize_message(payloads[ARM], JointState)
    assert joints.name[0] == "shoulder_pan" and len(joints.position) == 6
    transforms = deserialize_message(payloads["/tf"], TFMessage).transforms
    assert [t.child_frame_id for t in transforms][:2] == ["shoulder", "upper_arm"]
