"""`foxglove { }` adds a bridge process; a WebSocket client subscribes to channels and decodes messages."""

import asyncio
import json
import socket
import struct

import websockets
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState

from testsupport.compiled_settings import compiled_settings
from testsupport.joshuac_cli import joshuac

SUBPROTOCOL = "foxglove.sdk.v1"  # what foxglove-sdk 0.30 servers speak (the Foxglove app offers it)
MESSAGE_DATA_OPCODE = 0x01
WAIT_S = 30.0
ARM = "/arm/joint_states"


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def description(port: int) -> str:
    return f'''robot_config {{ name: "fx" mode: MODE_TELEOPERATION
      foxglove {{ port: {port} host: "127.0.0.1" }}
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 20 }}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "{ARM}" }} }}'''


async def first_messages(port: int, topics: list[str]) -> tuple[dict, dict]:
    """(advertised channel by topic, first payload by topic) once every topic has sent a message."""
    deadline = asyncio.get_running_loop().time() + WAIT_S
    while True:
        try:
            socket_ = await websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL])
            break
        except OSError:
            if asyncio.get_running_loop().time() > deadline:
                raise
            await asyncio.sleep(0.2)
    channels, payloads, subscribed = {}, {}, {}
    async with socket_:
        while len(payloads) < len(topics):
            frame = await asyncio.wait_for(socket_.recv(), deadline - asyncio.get_running_loop().time())
            if isinstance(frame, str):
                message = json.loads(frame)
                if message["op"] == "advertise":
                    for channel in message["channels"]:
                        channels[channel["topic"]] = channel
                        if channel["topic"] in topics and channel["topic"] not in subscribed.values():
                            subscription = len(subscribed) + 1
                            subscribed[subscription] = channel["topic"]
                            await socket_.send(
                                json.dumps(
                                    {
                                        "op": "subscribe",
                                        "subscriptions": [{"id": subscription, "channelId": channel["id"]}],
                                    }
                                )
                            )
            elif frame[0] == MESSAGE_DATA_OPCODE:
                subscription, _log_time = struct.unpack_from("<IQ", frame, 1)
                payloads.setdefault(subscribed[subscription], bytes(frame[13:]))
    return channels, payloads


def test_the_build_adds_a_bridge_process_serving_the_described_topics(tmp_path):
    source = tmp_path / "fx.pbtxt"
    source.write_text(description(8765))
    assert joshuac("build", source, "-o", tmp_path / "out").returncode == 0
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert "foxglove_bridge" in [p["name"] for p in manifest["processes"]]
    settings = compiled_settings(description(8765))["foxglove_bridge"]
    assert settings["type"] == "FOXGLOVE_BRIDGE" and settings["foxglove"] == {"port": 8765, "host": "127.0.0.1"}
    assert [t["name"] for t in settings["inputs"]] == [ARM]


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
