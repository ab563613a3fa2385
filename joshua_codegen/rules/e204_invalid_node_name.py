"""E204 invalid-node-name: a node name that breaks the ROS 2 node naming rules.

What it checks:
    A written node `name` matches [A-Za-z_][A-Za-z0-9_]* and is at most 128 characters long
    (it also names the node's entrypoint file and systemd unit).

Why it matters:
    rclpy refuses invalid node names at start-up, and the name becomes file and unit names.

Example:
    node {
      name: "front-camera"      # error: node name "front-camera" is invalid: it contains "-"
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.ros_names import node_name_problem
from joshua_codegen.rules.context import Finding

CODE = "E204"
NAME = "invalid-node-name"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    for view in ctx.nodes:
        if view.node.name:
            problem = node_name_problem(view.node.name)
            if problem is not None:
                hint = "".join(c if c.isascii() and (c.isalnum() or c == "_") else "_" for c in view.node.name)
                if hint[:1].isdigit():
                    hint = "_" + hint
                message = f'node name "{view.node.name}" is invalid: {problem}'
                if node_name_problem(hint) is None and hint != view.node.name:
                    message += f'; e.g. "{hint}"'
                yield Finding(view.at("name"), message)
