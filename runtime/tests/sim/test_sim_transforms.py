"""A simulated arm has /tf too: ROBOT_STATE_PUBLISHER runs beside the engine and follows its joint states."""

import numpy as np
import pytest
from sensor_msgs.msg import JointState
from sim_settings import ENCODER

from joshua_runtime.description.urdf_model import joint_transform, load, quaternion_xyzw
from testsupport.compiled_settings import compiled_settings
from testsupport.transform_pairs import transforms_with_states

WAIT_S = 60.0  # a cold MuJoCo process on a loaded machine
ARM = "/arm/joint_states"  # the simulated encoder's joint states (ENCODER)
RELIABLE = {"history": "KEEP_LAST", "depth": 100, "reliability": "RELIABLE", "durability": "VOLATILE"}


def test_the_simulated_arm_publishes_transforms_of_its_joint_states(start_node, ros_client):
    from tf2_msgs.msg import TFMessage

    settings = compiled_settings(f"""robot_config {{ name: "sim" mode: MODE_SIMULATION
      simulation {{ model: "builtin:so100" }}
      {ENCODER}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "{ARM}" }} }}""")
    assert set(settings) == {"arm_encoder", "state", "simulation"}
    ros_client.listen(ARM, JointState, RELIABLE, keep=500)
    ros_client.listen("/tf", TFMessage, RELIABLE, keep=500)
    engine = start_node(settings["simulation"])
    state = start_node(settings["state"])
    assert ros_client.spin_until(lambda: ros_client.count("/tf") >= 20, WAIT_S), engine.failure() + state.failure()
    model = load("builtin:so100")

    assert ros_client.spin_until(lambda: len(transforms_with_states(ros_client, ARM)) >= 5, WAIT_S), (
        ros_client.count(ARM),
        ros_client.count("/tf"),
    )
    matched = 0
    for message, joint_state in transforms_with_states(ros_client, ARM):
        positions = dict(zip(joint_state.name, joint_state.position))
        assert np.isfinite(positions["gripper"])
        for transform in message.transforms:
            joint = next(j for j in model.movable_joints if j.child == transform.child_frame_id)
            expected = joint_transform(joint, positions[joint.name])
            r = transform.transform.rotation
            assert [r.x, r.y, r.z, r.w] == pytest.approx(quaternion_xyzw(expected[:3, :3]), abs=1e-9)
            assert transform.transform.translation.x == pytest.approx(expected[0, 3])
        matched += 1
    assert matched >= 5, f"{matched} transforms matched a joint state"
