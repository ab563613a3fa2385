"""E402 camera-index-conflict: two camera nodes open the same camera index.

What it checks:
    Nodes that open a camera ({camera_types}) without a `video_source` use distinct `camera_index`
    values (default 0). The error is at the second camera, with the first as a note. With `host { }`
    blocks a camera belongs to its node's host: nodes on different hosts may both use index 0.

Why it matters:
    A V4L2 camera is opened by one process at a time; the second node fails to start or steals
    frames from the first.

Example:
    node { type: CAMERA_PUBLISHER topic_name: "/front" }
    node { type: CAMERA_PUBLISHER topic_name: "/wrist" }    # error: camera index 0 is already used
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.placement import node_host
from joshua_codegen.rules.context import Finding

TYPE_LISTS = {"camera_types": lambda entry: "camera" in entry.claims}
CODE = "E402"
NAME = "camera-index-conflict"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    owners = {}
    for view in ctx.typed_nodes:
        node = view.node
        if "camera" not in defaults.entry(node).claims or node.video_source:
            continue
        index = node.camera_index
        host = node_host(ctx.config, node)
        first = owners.setdefault((host, index), view)
        if first is not view:
            defaulted = "" if node.HasField("camera_index") else " (camera_index defaults to 0)"
            on = f' of host "{host}"' if host else ""
            yield Finding(
                view.at("camera_index"),
                f'camera index {index}{on} is already used by node "{first.name}"{defaulted}',
                ((first.at("camera_index"), "first used here"),),
            )
