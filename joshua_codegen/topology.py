"""Which node publishes, subscribes and reads which topic, with the field that says so: the one topology
function the rules and the planner both read.
"""

from dataclasses import dataclass

from joshua_codegen import defaults
from joshua_codegen.positions import Path, node_path
from joshua_codegen.ros_names import resolve_topic, topic_problem
from joshua_core import servo_topics
from joshua_core.node_families import TopicRole
from joshua_core.schema import robot_config_pb2 as pb

PUBLISHER, SUBSCRIBER, READER = "publisher", "subscriber", "reader"


@dataclass(frozen=True)
class Declaration:
    """One topic a node declares: its topic_name, state_topic, odom_topic, one of its input_topics,
    (CUSTOM) one of its `publishes` / `subscribes` entries, or one its type publishes by itself (/tf,
    /diagnostics: `implied`, located at the node's `type`).

    `message_type` is the declared or default type ("" for a reader: it takes its publishers' type);
    `qos` the node's resolved QoS (None for a reader: it matches its publishers).
    """

    index: int  # the node's position in the description
    node: str  # the node's name (its own or derived)
    topic: str  # fully qualified
    role: str  # PUBLISHER, SUBSCRIBER or READER
    message_type: str
    qos: dict | None
    at: Path  # the field that declares the topic (its qos_* fields are its siblings)
    implied: bool = False  # declared by the node type itself (/tf, /diagnostics, a preset channel), not by a field


def declarations(config: pb.RobotConfig, names: list[str]) -> list[Declaration]:
    """Every topic every typed node declares, in file order; topic names that are not valid are left
    out (E203 reports them)."""
    found = []
    for index, (node, name) in enumerate(zip(config.node, names)):
        for value, role, message_type, qos, field, implied in _declared(node):
            if topic_problem(value, name) is None:
                found.append(
                    Declaration(
                        index,
                        name,
                        resolve_topic(value, name),
                        role,
                        message_type,
                        qos,
                        node_path(index) + field,
                        implied,
                    )
                )
    return found


def _declared(node: pb.Node):
    """(topic as written, role, message type, QoS, field path within the node, implied) of each topic."""
    entry = defaults.entry(node)
    qos = defaults.qos(node)
    if entry.topic == TopicRole.PUBLISHES:
        yield node.topic_name, PUBLISHER, defaults.message_type(node), qos, ("topic_name",), False
    elif entry.topic == TopicRole.SUBSCRIBES:
        yield node.topic_name, SUBSCRIBER, defaults.message_type(node), qos, ("topic_name",), False
    if entry.state_topic and node.state_topic:
        yield node.state_topic, PUBLISHER, defaults.STATE_MESSAGE_TYPE, qos, ("state_topic",), False
    if entry.odom_topic:
        yield defaults.odom_topic(node), PUBLISHER, defaults.ODOM_MESSAGE_TYPE, qos, ("odom_topic",), False
    if entry.reads_inputs:
        for k, value in enumerate(node.input_topics):
            yield value, READER, "", None, ("input_topics", k), False
    if entry.declares_topics:
        for field, role in (("publishes", PUBLISHER), ("subscribes", SUBSCRIBER)):
            for k, topic in enumerate(getattr(node, field)):
                yield (
                    topic.topic_name,
                    role,
                    topic.message_type,
                    defaults.resolved_qos(topic),
                    (field, k, "topic_name"),
                    False,
                )
    for fixed in entry.fixed_topics:
        yield fixed.name, PUBLISHER, fixed.message_type, fixed.qos, ("type",), True
    if entry.diagnostics:
        yield (
            servo_topics.DIAGNOSTICS_TOPIC,
            PUBLISHER,
            servo_topics.DIAGNOSTICS_TYPE,
            servo_topics.FIXED_QOS,
            ("type",),
            True,
        )
    if entry.presets and node.topic_name:
        yield (
            servo_topics.preset_topic(node.topic_name),
            SUBSCRIBER,
            servo_topics.PRESET_TYPE,
            servo_topics.FIXED_QOS,
            ("topic_name",),
            True,
        )
