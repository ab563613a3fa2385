"""E103 node-type-unspecified: a node has no type.

What it checks:
    Every `node` sets `type` to a NodeType other than NODE_TYPE_UNSPECIFIED. Rules that depend on
    the type skip such nodes, so fix this first.

Why it matters:
    The type decides what the process does, which topics it uses and which fields it reads.

Example:
    node {
      topic_name: "/camera/image_raw"      # error: node #1 has no type
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding, label_of
from joshua_core.schema import Node

CODE = "E103"
NAME = "node-type-unspecified"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    types = [v.name for v in Node.DESCRIPTOR.fields_by_name["type"].enum_type.values if v.number]
    for view in ctx.nodes:
        if view.node.type == 0:
            yield Finding(view.at("type"), f"{label_of(view)} has no type; choose one of {', '.join(types)}")
