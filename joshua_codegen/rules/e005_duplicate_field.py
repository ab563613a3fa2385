"""E005 duplicate-field: a single-valued field (or map key) written twice in one block.

What it checks:
    A field that is not repeated appears at most once in its block, and an `env` key appears at
    most once. The note points at the first occurrence.

Why it matters:
    With two values it is unclear which one was meant (text format would keep one silently).

Example:
    node {
      qos_depth: 5
      qos_depth: 10      # error: field "qos_depth" is given twice in Node
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import DUPLICATE_FIELD

CODE = DUPLICATE_FIELD
NAME = "duplicate-field"
SEVERITY = ERROR
STAGE = "load"
