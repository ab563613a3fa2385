"""No episode event is lost when several come at once: a command's answer is never replaced by the next event.

A recorder answers `rerecord` at once and its writer process answers the discard afterwards; when the
user's next command is answered in between, the two events leave within milliseconds. A reliable topic
that keeps one event replaces the first before a busy client has it, and the client waits in vain.
"""

from joshua_runtime.ai import episode_protocol as protocol
from joshua_runtime.ai.episode_client import RecorderClient

RECORDER = "rec"
BURST = 20
DELIVERY_TIMEOUT_S = 20.0


def test_a_burst_of_events_reaches_the_client_whole(ros_domain):
    import rclpy
    from std_msgs.msg import String

    context = rclpy.Context()
    rclpy.init(context=context)
    node = rclpy.create_node(RECORDER, context=context)
    try:
        publisher = node.create_publisher(String, protocol.topic(RECORDER, protocol.STATE_TOPIC), protocol.state_qos())
        with RecorderClient(RECORDER, ros_domain) as client:
            assert client.spin_until(lambda: publisher.get_subscription_count() > 0, DELIVERY_TIMEOUT_S)
            for seq in range(1, BURST + 1):
                publisher.publish(String(data=protocol.encode({"seq": seq, "event": "started"})))
            client.spin_until(lambda: len(client.states) >= BURST, DELIVERY_TIMEOUT_S)
            assert [state["seq"] for state in client.states] == list(range(1, BURST + 1))
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)
