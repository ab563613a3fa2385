"""W101 field-not-applicable: a node sets a field its type ignores.

What it checks:
    Fields that only some node types read (defaults.FIELD_APPLIES_TO), e.g. `camera_index`
    (cameras), `serial_port` (servo buses and the lidar), `model_path` (INFERENCE), `executable`
    (CUSTOM), are not set on other types. A MOCK_* type reads what its real type reads.

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


def check(ctx):
    for view in ctx.typed_nodes:
        for field, types in defaults.FIELD_APPLIES_TO.items():
            if view.node.type not in types and is_set(view.node, field):
                yield Finding(view.at(field), f"{field} does not apply to {defaults.type_name(view.node.type)} "
                                              "and is ignored")
