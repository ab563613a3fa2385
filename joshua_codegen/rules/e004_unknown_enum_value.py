"""E004 unknown-enum-value: an enum field set to a name or number the enum does not define.

What it checks:
    Values of `mode`, `type`, `qos_reliability`, `qos_durability`, `qos_history`,
    `preferred_backend` and `restart` are names (or numbers) of their enum. The message suggests
    the closest name, or lists the valid ones.

Why it matters:
    proto3 keeps unknown enum numbers silently; the generated code would not know what to do.

Example:
    node {
      qos_reliability: BEST_EFORT    # error: unknown value "BEST_EFORT" ...; did you mean "BEST_EFFORT"?
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import UNKNOWN_ENUM_VALUE

CODE = UNKNOWN_ENUM_VALUE
NAME = "unknown-enum-value"
SEVERITY = ERROR
STAGE = "load"
