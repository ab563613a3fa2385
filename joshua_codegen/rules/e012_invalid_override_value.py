"""E012 invalid-override-value: a `--set` value that does not fit the field's type.

What it checks:
    The value is parsed like the field's type: integers and numbers as in text format, booleans
    as true/false, enum values by name (`MODE_SIMULATION`), strings as written (no quotes needed),
    repeated fields as a comma-separated list that replaces the whole list (`device_ids=1,2,3`;
    an empty value clears it). Message fields take no value themselves.

Why it matters:
    A value that cannot be stored must not be replaced by a guess.

Example:
    --set mode=SIMULATION          # error: unknown value "SIMULATION" for mode; did you mean "MODE_SIMULATION"?
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.overrides import INVALID_OVERRIDE_VALUE

CODE = INVALID_OVERRIDE_VALUE
NAME = "invalid-override-value"
SEVERITY = ERROR
STAGE = "override"
