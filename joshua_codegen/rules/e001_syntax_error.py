"""E001 syntax-error: the file is not protobuf text format.

What it checks:
    The text follows the protobuf text-format grammar: `field: value`, `field { ... }`,
    `field: [a, b]`, strings closed on the line they open, balanced braces, no `[extension]` names.
    Parsing stops at the first syntax error; every other load error is reported together.

Why it matters:
    Nothing after a syntax error can be read reliably, so no other check runs.

Example:
    robot_config {
      name: "arm"
      node { type: CAMERA_PUBLISHER      # error: expected "}" before the end of the file
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import SYNTAX_ERROR

CODE = SYNTAX_ERROR
NAME = "syntax-error"
SEVERITY = ERROR
STAGE = "load"
