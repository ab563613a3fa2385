"""W101 field-not-applicable: a node sets a field its type ignores.

What it checks:
    Fields that only some node types read (defaults.FIELD_APPLIES_TO), e.g. `camera_index`
    (cameras), `serial_port` (servo buses and the lidar), `model_path` (INFERENCE), `executable`
    (CUSTOM), are not set on other types. A MOCK_* type reads what its real type reads. A CUSTOM node
    ignores its own `topic_name`, `message_type` and `qos_*`: its topics are declared in
    `publishes { ... }` and `subscribes { ... }` blocks, with their own type and QoS.

Why it matters:
    The value has no effect, which usually means a copy-paste slip or a wrong node type.

Example:
    node {
      type: LIDAR_PUBLISHER
      camera_index: 0            # warning: camera_index does not apply to LIDAR_PUBLISHER and is ignored
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding, is_set

CODE = "W101"
NAME = "field-not-applicable"
SEVERITY = WARNING
STAGE = "check"


# What a node type whose topics are declared in blocks (CUSTOM) ignores on the node itself.
TOPIC_FIELDS = ("topic_name", "message_type", "qos_depth", "qos_reliability", "qos_durability", "qos_history")
DECLARE_INSTEAD = (
    "declare the program's topics in publishes { topic_name: ... message_type: ... } or subscribes { ... }"
)


def check(ctx):
    for view in ctx.typed_nodes:
        type_name = defaults.type_name(view.node.type)
        for field, types in defaults.FIELD_APPLIES_TO.items():
            if view.node.type not in types and is_set(view.node, field):
                yield Finding(view.at(field), f"{field} does not apply to {type_name} and is ignored")
        if defaults.entry(view.node).declares_topics:
            for field in TOPIC_FIELDS:
                if is_set(view.node, field):
                    yield Finding(
                        view.at(field), f"{field} does not apply to {type_name} and is ignored; " + DECLARE_INSTEAD
                    )
