"""E010 malformed-override: a `--set` argument that is not `KEY=VALUE`.

What it checks:
    Each `--set` argument has a non-empty key, an `=`, and a key made of dot-separated names
    (`mode`, `shutdown.sigint_grace_s`, `NODE_NAME.qos_depth`). Diagnostics about overrides are
    reported at path `--set`, line = the override's position on the command line (1-based).

Why it matters:
    A malformed override is a typing mistake on the command line; ignoring it would build
    something other than what was asked.

Example:
    joshuac check robot.pbtxt --set mode     # --set:1:1: error[E010]: expected KEY=VALUE
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.overrides import MALFORMED_OVERRIDE

CODE = MALFORMED_OVERRIDE
NAME = "malformed-override"
SEVERITY = ERROR
STAGE = "override"
