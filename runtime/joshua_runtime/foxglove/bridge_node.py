"""FOXGLOVE_BRIDGE process: serve the robot's topics over the Foxglove WebSocket protocol (foxglove-sdk).

Settings used: `inputs` (the topics of the description with their types and a QoS matching their
publishers, written by joshuac), `foxglove.host` and `foxglove.port`. Each topic becomes one channel
with a `ros2msg` schema (the full message definition) and `cdr` messages, forwarded as DDS delivers
them (serialized, never decoded) and only while a client subscribes. Topics that appear in the graph
later (publishers outside the description) are added as they are discovered, every
DISCOVERY_PERIOD_S, subscribed with a QoS all their discovered publishers serve.

A topic whose publishers all keep messages for late subscribers (transient local: /tf_static,
/robot_description) is subscribed transient local, and the bridge keeps its newest messages (as many
as the subscription's depth) to send to each client that subscribes to its channel later, as a ROS
subscriber would get them on joining. The SDK's Python API sends to every subscriber of a channel,
not to one client: clients already subscribed get those messages again.
"""

import time

from rclpy.qos import DurabilityPolicy

from joshua_runtime.bags.message_definitions import full_definition
from joshua_runtime.errors import DeviceError, JoshuaError
from joshua_runtime.foxglove.kept_messages import KeptMessages
from joshua_runtime.messages import message_class
from joshua_runtime.node import JoshuaNode
from joshua_runtime.qos import qos_profile
from joshua_runtime.tools.topic_graph import subscription_qos

DISCOVERY_PERIOD_S = 2.0
# Topics every ROS node has, of no interest to a viewer.
IGNORED_TOPICS = frozenset({"/rosout", "/parameter_events"})


class FoxgloveBridgeNode(JoshuaNode):
    server = None

    def start(self) -> None:
        import foxglove

        from joshua_runtime.foxglove.replay_listener import ReplayKeptMessages

        self.foxglove = foxglove
        self.channels: dict[str, object] = {}
        self.kept: dict[str, KeptMessages] = {}  # by topic, for transient-local topics
        self.subscriptions = []
        for topic in self.settings.inputs:  # before the server: a client that connects finds every channel there
            if topic.message_type:
                self._bridge(topic.name, topic.message_type, qos_profile(topic.qos))
        try:
            self.server = foxglove.start_server(
                name=self.settings.robot or self.name,
                host=self.settings.foxglove.host,
                port=self.settings.foxglove.port,
                server_listener=ReplayKeptMessages(self.replay_kept),
            )
        except Exception as exc:  # the SDK reports a busy port as a RuntimeError of its own
            raise DeviceError(
                f"cannot serve Foxglove on {self.settings.foxglove.host}:{self.settings.foxglove.port}: {exc}"
            ) from exc
        self._discover()
        self.ros.create_timer(DISCOVERY_PERIOD_S, self._discover)
        self.log.info(f"serving {len(self.channels)} topics on ws://{self.settings.foxglove.host}:{self.server.port}")

    def _bridge(self, topic: str, message_type: str, qos) -> None:
        try:
            schema = self.foxglove.Schema(
                name=message_type, encoding="ros2msg", data=full_definition(message_type).encode()
            )
            ros_class = message_class(message_type)
        except JoshuaError as exc:
            self.log.warning(f"{topic} is not served: {exc}")
            self.channels[topic] = None
            return
        channel = self.foxglove.Channel(topic, schema=schema, message_encoding="cdr")
        kept = None
        if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            kept = self.kept[topic] = KeptMessages(qos.depth)
        self.channels[topic] = channel

        def forward(data: bytes) -> None:
            log_time = time.time_ns()
            if kept is not None:
                kept.keep(data, log_time)
            if channel.has_sinks():
                channel.log(data, log_time=log_time)

        self.subscriptions.append(self.ros.create_subscription(ros_class, topic, forward, qos, raw=True))

    def _discover(self) -> None:
        for topic, types in self.ros.get_topic_names_and_types():
            if topic in self.channels or topic in IGNORED_TOPICS or len(types) != 1:
                continue
            publishers = self.ros.get_publishers_info_by_topic(topic)
            if publishers:
                self._bridge(topic, types[0], subscription_qos(publishers))

    def replay_kept(self, topic: str) -> None:
        """Send the kept messages of `topic` to its channel's subscribers (a client just subscribed)."""
        kept, channel = self.kept.get(topic), self.channels.get(topic)
        if kept is not None and channel is not None:
            for data, log_time in kept.snapshot():
                channel.log(data, log_time=log_time)

    def close(self) -> None:
        if self.server is not None:
            self.server.stop()
