"""E006 missing-robot-config: the file is empty or its root is not `robot_config { ... }`.

What it checks:
    The file holds one `robot_config { ... }` block at its root, and robot fields (`name`, `mode`,
    `node`, ...) are written inside it.

Why it matters:
    An empty file or a wrong root describes no robot at all.

Example:
    name: "arm"          # error: "name" belongs inside robot_config { ... }
    mode: MODE_TELEOPERATION
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import MISSING_ROBOT_CONFIG

CODE = MISSING_ROBOT_CONFIG
NAME = "missing-robot-config"
SEVERITY = ERROR
STAGE = "load"
