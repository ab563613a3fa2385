"""The topics a node type publishes by itself (its registry entry's fixed_topics) are what its runtime
publishes, with those types and QoS: the compiler's topology and W202 rely on it."""

import pytest
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy

from joshua_core.node_types import NODE_TYPES
from testsupport.compiled_settings import compiled_settings

DISCOVERY_TIMEOUT_S = 20.0
# Node types with fixed topics that run without a device (a real base shares the mock's ROS side).
RUNNABLE = sorted(name for name, entry in NODE_TYPES.items() if entry.fixed_topics and not entry.hardware)
FIELDS = {
    "ROBOT_STATE_PUBLISHER": 'topic_name: "/joints"',
    "MOCK_DIFF_DRIVE_BASE": 'topic_name: "/cmd_vel"',
}


def test_the_runnable_types_cover_every_family_with_fixed_topics():
    families = {entry.family for entry in NODE_TYPES.values() if entry.fixed_topics}
    assert families == {NODE_TYPES[name].family for name in RUNNABLE}
    assert set(RUNNABLE) == set(FIELDS)


@pytest.mark.parametrize("node_type", RUNNABLE)
def test_a_node_publishes_its_fixed_topics_with_the_registry_types_and_qos(node_type, start_node, ros_client):
    settings = compiled_settings(f"""robot_config {{ name: "r" mode: MODE_TELEOPERATION
      node {{ name: "fixed" type: {node_type} {FIELDS[node_type]} }} }}""")
    node = start_node(settings["fixed"])
    for topic in NODE_TYPES[node_type].fixed_topics:
        found = [i for i in ros_client.publishers_info(topic.name, DISCOVERY_TIMEOUT_S) if i.node_name == "fixed"]
        # Discovery does not carry the history depth (Fast DDS reports 0): types and policies are compared.
        assert [(i.topic_type, i.qos_profile.reliability, i.qos_profile.durability) for i in found] == [
            (topic.message_type, ReliabilityPolicy[topic.reliability], DurabilityPolicy[topic.durability])
        ], f"{topic.name}: {node.failure()}"
