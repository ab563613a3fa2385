"""Helpers of the sensor tests: expected QoS and timeouts, and the waits they make on the ros_client fixture.

Node settings come from the compiler (testsupport/compiled_settings.py), node processes from
testsupport/node_process.py and the in-process rclpy client from testsupport/ros_client.py.
"""

from joshua_core import so100
from testsupport.node_process import NodeProcess
from testsupport.ros_client import RosClient

NODE_START_TIMEOUT_S = 30.0  # a cold rclpy process on a busy 2-core machine
MESSAGE_TIMEOUT_S = 15.0

# The QoS joshuac gives camera and lidar publishers, and every other node, when the description sets none.
SENSOR_QOS = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}
DEFAULT_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
SO100_JOINTS = list(so100.SO100_JOINTS)


def publishers(client: RosClient, topic: str, node: NodeProcess) -> list:
    """The publishers of `topic` once discovery names them; fails at once with the node's output if it exits."""

    def still_running() -> None:
        assert node.process.poll() is None, f"node exited before publishing {topic}: {node.failure()}"

    return client.publishers_info(topic, NODE_START_TIMEOUT_S, every=still_running)


def collect(
    client: RosClient, message_class, topic: str, qos: dict, count: int, timeout_s: float = MESSAGE_TIMEOUT_S
) -> list:
    """The first `count` messages on `topic` received by a subscription of `qos` made now."""
    client.listen(topic, message_class, qos, keep=count)
    received = client.spin_until(lambda: client.count(topic) >= count, timeout_s)
    assert received, f"{client.count(topic)} of {count} messages on {topic} within {timeout_s} s"
    return client.messages(topic)
