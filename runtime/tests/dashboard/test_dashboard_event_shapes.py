"""The events the dashboard makes of ROS messages and of its recorder and inference nodes, as the broadcaster
sends them, are what the API schema says (the robots of the browser tests publish no scan or inference)."""

import asyncio
import json
from types import SimpleNamespace

import pytest
from api_contract import check_event
from sensor_msgs.msg import Image, JointState, LaserScan

from joshua_runtime.ai import episode_protocol
from joshua_runtime.ai.episode_session import EpisodeSession
from joshua_runtime.dashboard import frames
from joshua_runtime.dashboard.broadcaster import Broadcaster
from joshua_runtime.dashboard.robot_view import Inference
from joshua_runtime.dashboard.telemetry import inference_event, recorder_event


def sent(kind: str, data: dict) -> dict:
    """`data` as a page receives it in an event of `kind` (stamped with the server's clock)."""

    async def through_broadcaster():
        broadcaster = Broadcaster()
        broadcaster.attach(asyncio.get_running_loop())
        mailbox = broadcaster.subscribe()
        broadcaster.publish(kind, kind, data)
        return await mailbox.get()

    event = asyncio.run(through_broadcaster())
    assert event.kind == kind
    return json.loads(event.data)


def test_joint_state_image_and_scan_events_match_the_schema():
    joints = JointState(name=["pan", "gripper"], position=[0.5, float("nan")], velocity=[1.0, 2.0], effort=[])
    check_event("joints", sent("joints", frames.joint_state_event("/arm/joint_states", joints)))
    image = Image(width=4, height=2, encoding="rgb8", step=12, data=bytes(24))
    check_event("image", sent("image", frames.image_event("/camera/image_raw", image)))
    scan = LaserScan(angle_min=-1.0, angle_increment=0.5, range_max=4.0, ranges=[1.0, float("inf"), 2.5])
    check_event("scan", sent("scan", frames.scan_event("/scan", scan)))


def test_recorder_and_inference_events_match_the_schema():
    state = {"seq": 4, "event": "started", "recording": True, "message": "episode 3"}
    writer = SimpleNamespace(start_episode=lambda task: None)
    log = SimpleNamespace(info=lambda text: None)
    session = EpisodeSession(writer, lambda event, **details: None, log, "pick", episode_time_s=30.0)
    session.begin()
    # as the recorder sends it
    progress = json.loads(episode_protocol.encode(session.progress(writer_ready=False, last_event=1)))
    check_event("recorder", sent("recorder", recorder_event("recorder", state, progress, 3)))
    check_event("recorder", sent("recorder", recorder_event("recorder", {}, None, 0)))
    policy = Inference("policy", "/models/act", 30.0, ("/camera/image_raw", "/arm/joint_states"), "/arm/command")
    check_event("inference", sent("inference", inference_event(policy, 29.5, ["/camera/image_raw"])))


def test_an_event_of_another_shape_fails_the_check():
    joints = sent("joints", frames.joint_state_event("/j", JointState(name=["pan"], position=[0.5])))
    with pytest.raises(AssertionError, match="position"):
        check_event("joints", {**joints, "position": ["0.5"]})
    with pytest.raises(AssertionError, match="server_time_s"):
        check_event("joints", {key: value for key, value in joints.items() if key != "server_time_s"})
    with pytest.raises(AssertionError, match="not one of the API schema"):
        check_event("joint", joints)
