"""ROBOT_STATE_PUBLISHER over DDS: the URDF, the fixed frames and /tf from a mock arm's joint states."""

import numpy as np
import pytest
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from joshua_runtime.description.urdf_model import joint_transform, load, quaternion_xyzw
from testsupport.compiled_settings import compiled_settings
from testsupport.transform_pairs import transforms_with_states

WAIT_S = 20.0
ARM = "/arm/joint_states"
KEPT = 2000
RELIABLE = {"history": "KEEP_LAST", "depth": 100, "reliability": "RELIABLE", "durability": "VOLATILE"}
LATCHED = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}


def test_transforms_follow_the_joint_states(start_node, ros_client):
    from tf2_msgs.msg import TFMessage

    settings = compiled_settings(f'''robot_config {{ name: "r" mode: MODE_TELEOPERATION
      node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{ARM}" rate_hz: 20 }}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "{ARM}" }} }}''')
    assert settings["state"]["robot_description"] == "builtin:so100"
    # Both kept for 100 s at 20 Hz, so that the stamps of the transforms find the joint states they came from.
    ros_client.listen(ARM, JointState, RELIABLE, keep=KEPT)
    ros_client.listen("/tf", TFMessage, RELIABLE, keep=KEPT)
    start_node(settings["arm"])
    publisher = start_node(settings["state"])
    assert ros_client.spin_until(lambda: ros_client.count("/tf") >= 10, WAIT_S), publisher.failure()
    ros_client.listen("/tf_static", TFMessage, LATCHED)
    ros_client.listen("/robot_description", String, LATCHED)
    assert ros_client.spin_until(
        lambda: ros_client.last("/tf_static") and ros_client.last("/robot_description"), WAIT_S
    ), publisher.failure()

    model = load("builtin:so100")
    assert ros_client.last("/robot_description").data == model.text
    [laser] = ros_client.last("/tf_static").transforms
    assert (laser.header.frame_id, laser.child_frame_id) == ("base_link", "laser")

    assert ros_client.spin_until(lambda: len(transforms_with_states(ros_client, ARM)) >= 5, WAIT_S), (
        ros_client.count(ARM),
        ros_client.count("/tf"),
    )
    compared = 0
    for tf, state in transforms_with_states(ros_client, ARM):
        positions = dict(zip(state.name, state.position))
        assert [t.child_frame_id for t in tf.transforms] == [j.child for j in model.movable_joints]
        for transform in tf.transforms:
            joint = next(j for j in model.movable_joints if j.child == transform.child_frame_id)
            expected = joint_transform(joint, positions[joint.name])
            t, r = transform.transform.translation, transform.transform.rotation
            assert [t.x, t.y, t.z] == pytest.approx(expected[:3, 3])
            assert [r.x, r.y, r.z, r.w] == pytest.approx(quaternion_xyzw(expected[:3, :3]))
        compared += 1
    assert compared >= 5
    assert np.ptp([m.position[0] for m in ros_client.messages(ARM)]) > 0  # the arm moved
