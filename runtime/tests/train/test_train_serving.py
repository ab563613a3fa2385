"""A PPO reach policy served by the INFERENCE node moves the simulated arm toward its goal.

Both processes are compiled by joshuac from one MODE_SIMULATION description: the simulation
engine stands in for the encoder and the actuator; the INFERENCE node reads the encoder's joint
states and commands the actuator. The goal is the one in the policy's joshua_policy.json.
"""

import numpy as np
from sensor_msgs.msg import JointState

from joshua_runtime.ai import saved_policy
from joshua_runtime.sim import arm_task as arm
from testsupport.compiled_settings import compiled_settings

RELIABLE = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
STARTUP_TIMEOUT_S = 90.0
REACH_TIMEOUT_S = 30.0
# The policy reaches the goal within ~0.05 m in simulation (see the learning test); served over ROS
# at 20 Hz it must at least halve the distance it starts from.
CLOSE_ENOUGH_M = 0.06


def description(model_path) -> str:
    return f"""robot_config {{
  name: "served_reach"
  mode: MODE_SIMULATION
  simulation {{ model: "builtin:so100" }}
  node {{ name: "arm_encoder" type: ENCODER_PUBLISHER topic_name: "/arm/joint_states" serial_port: "/dev/ttyACM0" rate_hz: 50 }}
  node {{ name: "arm_actuator" type: ACTUATOR_SUBSCRIBER topic_name: "/arm/command" serial_port: "/dev/ttyACM1" rate_hz: 50 }}
  node {{ name: "reach_policy" type: INFERENCE topic_name: "/arm/command" model_path: "{model_path}"
          input_topics: ["/arm/joint_states"] rate_hz: 20 }}
}}
"""


def test_served_ppo_policy_brings_the_simulated_grasp_point_to_the_goal(trained_reach, start_node, ros_client):
    output, _ = trained_reach
    goal = np.array(saved_policy.read(output)["goal"])
    settings = compiled_settings(description(output))
    kinematics = arm.ArmKinematics()
    ros_client.listen("/arm/joint_states", JointState, RELIABLE)
    ros_client.listen("/arm/command", JointState, RELIABLE)

    def distance() -> float | None:
        state = ros_client.last("/arm/joint_states")
        if state is None:
            return None
        by_name = dict(zip(state.name, state.position))
        return float(np.linalg.norm(kinematics.grasp_point([by_name[j] for j in arm.ARM_JOINTS]) - goal))

    simulation = start_node(settings["simulation"])
    assert ros_client.spin_until(lambda: distance() is not None, STARTUP_TIMEOUT_S), simulation.failure()
    start = distance()
    assert start > 2 * CLOSE_ENOUGH_M
    policy = start_node(settings["reach_policy"])
    assert ros_client.spin_until(lambda: ros_client.last("/arm/command") is not None, STARTUP_TIMEOUT_S), (
        policy.failure()
    )
    assert list(ros_client.last("/arm/command").name) == list(arm.ARM_JOINTS)
    reached = ros_client.spin_until(lambda: distance() < CLOSE_ENOUGH_M, REACH_TIMEOUT_S)
    assert reached, f"grasp point still {distance():.3f} m from the goal (started {start:.3f} m away)"
