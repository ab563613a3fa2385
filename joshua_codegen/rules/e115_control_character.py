"""E115 control-character: a string holds a control character or a line break.

What it checks:
    No string anywhere in the description (names, paths, topics, args, env keys and values, ...)
    contains a control character (C0: newline, tab, NUL, ...; DEL; C1: U+0080-U+009F), a Unicode
    line separator (U+0085, U+2028, U+2029), or the noncharacters U+FFFE and U+FFFF.

Why it matters:
    Strings end up in unit files, INI sections and command lines, where a line break or NUL
    cannot be represented faithfully and could inject configuration. C++ nodes read their
    settings through rcl's YAML parser, which refuses C1 controls, U+FFFE and U+FFFF (the node
    would not start) and folds U+0085 into a space.

Example:
    node {
      serial_port: "/dev/ttyUSB0\n"      # error: serial_port contains a control character (U+000A)
    }
"""

import unicodedata

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding, strings_of

CODE = "E115"
NAME = "control-character"
SEVERITY = ERROR
STAGE = "check"
LINE_SEPARATORS = {"\x85", "\u2028", "\u2029"}
NONCHARACTERS = {"\ufffe", "\uffff"}


def _bad_char(text: str) -> str | None:
    for char in text:
        if char in LINE_SEPARATORS or char in NONCHARACTERS or unicodedata.category(char) == "Cc":
            return char
    return None


def check(ctx):
    for path, what, text in strings_of(ctx.description):
        char = _bad_char(text)
        if char in NONCHARACTERS:
            yield Finding(path, f"{what} contains U+{ord(char):04X}, which is not a character; remove it")
        elif char is not None:
            yield Finding(
                path,
                f"{what} contains a control character (U+{ord(char):04X}); "
                "remove line breaks, tabs and other control characters",
            )
