"""E002 unknown-field: a field name the schema does not have.

What it checks:
    Every field name exists in its message (RobotDescription, RobotConfig, Node, Shutdown,
    Simulation). The message suggests the closest name, or the block the field belongs in.

Why it matters:
    A misspelt field would otherwise be dropped silently and its default used instead.

Example:
    node {
      type: CAMERA_PUBLISHER
      qos_dept: 5      # error: unknown field "qos_dept" in Node; did you mean "qos_depth"?
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import UNKNOWN_FIELD

CODE = UNKNOWN_FIELD
NAME = "unknown-field"
SEVERITY = ERROR
STAGE = "load"
