"""E007 unreadable-file: the description file cannot be read.

What it checks:
    The path names a readable regular file (not missing, not a directory, readable by the user).

Why it matters:
    Nothing can be checked or built from a file that cannot be read.

Example:
    joshuac check config/robots/   # error: cannot read the file: it is a directory
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import UNREADABLE_FILE

CODE = UNREADABLE_FILE
NAME = "unreadable-file"
SEVERITY = ERROR
STAGE = "load"
