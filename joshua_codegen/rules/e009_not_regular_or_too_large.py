"""E009 not-regular-or-too-large: the description path is not a regular file, or the file is over 1 MiB.

What it checks:
    The path names a regular file (not a FIFO, a device, a socket or a pseudo file of /proc or
    /sys, whose size says nothing about what it yields) of at most 1 MiB (1048576 bytes; a 3000-node description is about 0.3 MiB).

Why it matters:
    Reading a FIFO blocks forever and a device like /dev/urandom never ends; a huge file takes
    minutes and gigabytes. joshuac refuses them at once, after reading at most 1 MiB + 1 byte.

Example:
    joshuac check /dev/urandom   # error: the path is a character device, not a regular file
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.load import NOT_REGULAR_FILE

CODE = NOT_REGULAR_FILE
NAME = "not-regular-or-too-large"
SEVERITY = ERROR
STAGE = "load"
