"""E003 invalid-value: a value that does not fit its field's type.

What it checks:
    Integers are integers within the field's range (uint32: 0 to 4294967295), numbers are numbers,
    booleans are true/false, strings are quoted with valid escapes and valid UTF-8, messages are
    written as `{ ... }`, and only repeated fields take lists.

Why it matters:
    A value of the wrong shape cannot be stored; guessing what was meant could drive hardware wrongly.

Example:
    node {
      qos_depth: 99999999999     # error: qos_depth takes an unsigned 32-bit integer (0 to 4294967295)
      device_ids: [1, "2"]       # error: device_ids takes an integer, not a string
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import INVALID_VALUE

CODE = INVALID_VALUE
NAME = "invalid-value"
SEVERITY = ERROR
STAGE = "load"
