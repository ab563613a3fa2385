"""W202 unpublished-topic: a node subscribes to a topic that nothing in the description publishes.

What it checks:
    Each subscription (topic_name of {subscriber_types}, every input_topics entry of {reader_types}, and every
    topic a CUSTOM node declares in `subscribes`) has a publisher in the description; processes
    outside it are not known.

    Topics a node publishes by its type alone count too (its registry entry's fixed_topics, e.g. /tf,
    /tf_static and /robot_description). When a published topic is spelt alike, the message suggests
    it. An actuator's preset channel (`<topic_name>/preset`) is left out: it is published by hand or
    by joshua-desktop when needed.

Why it matters:
    Unless something outside the description publishes it, the node waits forever for data. An
    input_topics entry published outside gets a best-effort subscription (it accepts any
    publisher), and its message type is learnt from the ROS graph when the node starts.

Example:
    node {
      type: ACTUATOR_SUBSCRIBER
      topic_name: "/arm/commands"    # warning: nothing in this description publishes "/arm/commands"
    }
    node {
      type: INFERENCE
      input_topics: ["/camera/imag_raw"]  # warning: ... publishes "/camera/imag_raw"; did you mean "/camera/image_raw"?
    }
"""

from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding
from joshua_codegen.values import suggest
from joshua_core.node_families import TopicRole

TYPE_LISTS = {
    "subscriber_types": lambda entry: entry.topic == TopicRole.SUBSCRIBES,
    "reader_types": lambda entry: entry.reads_inputs,
}
CODE = "W202"
NAME = "unpublished-topic"
SEVERITY = WARNING
STAGE = "check"
NEEDS_EVERY_NODE = True


def check(ctx):
    for index in (ctx.subscribers, ctx.readers):
        for topic, endpoints in index.items():
            reported = [endpoint for endpoint in endpoints if not endpoint.implied]
            if topic in ctx.publishers or not reported:
                continue
            hint = suggest(topic, ctx.publishers)  # compares with every publisher: only for a warning given
            message = f'nothing in this description publishes "{topic}"'
            message += f'; did you mean "{hint}"?' if hint else ""
            for endpoint in reported:
                yield Finding(endpoint.at, message)
