"""E008 not-text: the file is not UTF-8 text (invalid bytes or NUL characters).

What it checks:
    The file decodes as UTF-8 and holds no NUL character; the position is the first bad byte.

Why it matters:
    A binary file, or a file saved in another encoding, would be misread character by character.

Example:
    A file saved as Latin-1 with `name: "bras_articulé"` — error at the byte of the "é".
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import NOT_TEXT

CODE = NOT_TEXT
NAME = "not-text"
SEVERITY = ERROR
STAGE = "load"
