"""E115 control-character: a string holds a control character or a line break.

What it checks:
    No string anywhere in the description (names, paths, topics, args, env keys and values, ...)
    contains a C0 control character (newline, tab, NUL, ...), DEL, or a Unicode line separator
    (U+0085, U+2028, U+2029).

Why it matters:
    Strings end up in unit files, INI sections and command lines, where a line break or NUL
    cannot be represented faithfully and could inject configuration.

Example:
    node {
      serial_port: "/dev/ttyUSB0\n"      # error: serial_port contains a control character (U+000A)
    }
"""

from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding

CODE = "E115"
NAME = "control-character"
SEVERITY = ERROR
STAGE = "check"
LINE_SEPARATORS = {"\x85", "\u2028", "\u2029"}


def _bad_char(text: str) -> str | None:
    for char in text:
        if char < " " or char == "\x7f" or char in LINE_SEPARATORS:
            return char
    return None


def _strings(message, path):
    """(path, field name, text) of every string in a message, recursively."""
    for fd, value in message.ListFields():
        field_path = path + (fd.name,)
        if fd.message_type is not None and fd.message_type.GetOptions().map_entry:
            for key, item in value.items():
                yield field_path + (key,), f"{fd.name} name", key
                yield field_path + (key,), f"{fd.name} value of {key}", item
        elif fd.message_type is not None:
            items = value if fd.is_repeated else [value]
            for index, item in enumerate(items):
                yield from _strings(item, field_path + (index,) if fd.is_repeated else field_path)
        elif fd.type == FieldDescriptor.TYPE_STRING:
            if fd.is_repeated:
                for index, item in enumerate(value):
                    yield field_path + (index,), fd.name, item
            else:
                yield field_path, fd.name, value


def check(ctx):
    for path, what, text in _strings(ctx.description, ()):
        char = _bad_char(text)
        if char is not None:
            yield Finding(path, f"{what} contains a control character (U+{ord(char):04X}); "
                                "remove line breaks, tabs and other control characters")
