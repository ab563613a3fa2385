"""E011 unknown-override-target: a `--set` key that names no field or no node.

What it checks:
    The key is a robot field (`mode`, `name`, `ros_domain_id`, ...), a field of `shutdown` or
    `simulation` (`shutdown.sigint_grace_s`), an `env` entry (`env.NAME`), or `NODE_NAME.FIELD`
    where NODE_NAME is a node's name (its own, or the one derived from its type). Nodes are not
    addressed by index. The message suggests the closest field or node name.

Why it matters:
    An override of nothing would silently leave the description unchanged.

Example:
    --set camera.qos_depth=3        # error: no node named "camera"; did you mean "camera_publisher"?
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.overrides import UNKNOWN_OVERRIDE_TARGET

CODE = UNKNOWN_OVERRIDE_TARGET
NAME = "unknown-override-target"
SEVERITY = ERROR
STAGE = "override"
