"""Escaping of values that enter generated files: one function per target language."""

import json
import posixpath
import re
import shlex
from json.encoder import encode_basestring_ascii


def python_literal(value, indent: int = 0) -> str:
    """A Python expression that evaluates to `value` (dicts, lists, str, int, float, bool, None).

    Strings go through repr(), so quotes, newlines, backslashes and `$` stay data. Dicts keep their
    insertion order (deterministic); one key per line for readable diffs.
    """
    if isinstance(value, str) or value is None or isinstance(value, (bool, int)):  # most values: first
        return repr(value)
    pad = " " * indent
    inner = " " * (indent + 4)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{inner}{str(k)!r}: {python_literal(v, indent + 4)}," for k, v in value.items()]
        return "{\n" + "\n".join(items) + f"\n{pad}}}"
    if isinstance(value, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in value):
            return "[" + ", ".join(python_literal(v) for v in value) + "]"
        items = [f"{inner}{python_literal(v, indent + 4)}," for v in value]
        return "[\n" + "\n".join(items) + f"\n{pad}]"
    if isinstance(value, float):
        return repr(value) if value == value and abs(value) != float("inf") else f"float({str(value)!r})"
    raise TypeError(f"cannot write {type(value).__name__} as a Python literal")


def json_document(value, indent: int = 0) -> str:
    """`value` (dicts with str keys, lists, str, int, float, bool, None) as JSON, byte for byte what
    `json.dumps(value, indent=2, ensure_ascii=True)` writes: json's indenting encoder is pure Python and
    took most of a large manifest's time, while its string escaping is C (used here for every string)."""
    if isinstance(value, str):
        return encode_basestring_ascii(value)
    if value is None or isinstance(value, bool):
        return _JSON_CONSTANTS[value]
    if isinstance(value, int):
        return int.__repr__(value)
    if isinstance(value, float):
        return float.__repr__(value) if value == value and abs(value) != float("inf") else json.dumps(value)
    inner = "\n" + " " * (indent + 2)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = (f"{encode_basestring_ascii(key)}: {json_document(item, indent + 2)}" for key, item in value.items())
        return "{" + inner + ("," + inner).join(items) + "\n" + " " * indent + "}"
    if isinstance(value, (list, tuple)):
        if not value:
            return "[]"
        return (
            "["
            + inner
            + ("," + inner).join(json_document(item, indent + 2) for item in value)
            + "\n"
            + " " * indent
            + "]"
        )
    raise TypeError(f"cannot write {type(value).__name__} as JSON")


_JSON_CONSTANTS = {None: "null", True: "true", False: "false"}


def ros_parameter(value) -> str:
    """The value of a ROS 2 `-p name:=value` argument, which rcl parses as YAML, keeping its type.

    Strings are always single-quoted (a quote inside is doubled): rcl reads a plain scalar as the
    type it looks like, so `yes`, `-1`, `1e3`, `~` or `[1]` would arrive as a bool, integer,
    double or array, not as the string the node declared. Lists become flow sequences `[a, b]`,
    booleans `true`/`false`, numbers their shortest exact form (`.inf`/`.nan` when not finite).
    rcl cannot parse C1 controls, U+FFFE or U+FFFF even quoted; the rules refuse them (E115).
    """
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(ros_parameter(item) for item in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value != value:
            return ".nan"
        if abs(value) == float("inf"):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    raise TypeError(f"cannot write {type(value).__name__} as a ROS parameter")


_SHELL_BARE = re.compile(r"[A-Za-z0-9_@%+=:,./-]+")
_SHELL_SPECIAL_IN_DOUBLE_QUOTES = set('"$`\\!')


def shell_word(text: str) -> str:
    """One POSIX shell word: bare when plain, in double quotes when that needs no escape (so the
    single quotes of a ROS parameter stay readable), else shlex's single quotes."""
    if _SHELL_BARE.fullmatch(text):
        return text
    if not _SHELL_SPECIAL_IN_DOUBLE_QUOTES.intersection(text):
        return f'"{text}"'
    return shlex.quote(text)


def one_line(text: str) -> str:
    """Text safe inside a one-line comment of any target: control characters become escapes."""
    return json.dumps(text, ensure_ascii=True)[1:-1]


def ansible_value(value) -> str:
    """A YAML scalar for an Ansible inventory or playbook: numbers and booleans as JSON (YAML reads JSON),
    strings JSON-quoted and tagged `!unsafe`, so Ansible never takes a `{{` in them for a template."""
    if isinstance(value, str):
        return "!unsafe " + json.dumps(value, ensure_ascii=True)
    return json.dumps(value)


def xml_comment(text: str) -> str:
    """Text safe inside an XML comment: one line, and no `--`, which would end the comment."""
    return re.sub(r"-(?=-)", "- ", one_line(text))


def dot_id(text: str) -> str:
    """A quoted Graphviz DOT identifier."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def mermaid_label(text: str) -> str:
    """A quoted Mermaid label; quotes and brackets become HTML entities Mermaid understands."""
    return '"' + text.translate(_MERMAID_ENTITIES) + '"'


_MERMAID_ENTITIES = str.maketrans({"&": "&amp;", '"': "&quot;", "<": "&lt;", ">": "&gt;", "\n": " ", "#": "&num;"})


_SYSTEMD_BARE = re.compile(r"[A-Za-z0-9_@%+=:,./~-]+")
_SYSTEMD_ESCAPES = str.maketrans(  # control characters as \xNN, except those with a C escape
    {chr(code): f"\\x{code:02x}" for code in [*range(0x20), 0x7F]}
    | {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\t": "\\t", "\r": "\\r"}
)
_CONTROL_CHARACTER = re.compile("[\x00-\x1f\x7f]")


def systemd_quote(text: str, exec_line: bool = True) -> str:
    """One word of a systemd unit setting: an Exec*= argument, or (exec_line=False) an Environment=
    assignment. `%` specifiers become `%%`; in Exec lines `$` variables become `$$`; anything else
    than plain path characters is double-quoted with C escapes, control characters as \\xNN."""
    text = text.replace("%", "%%")
    if exec_line:
        text = text.replace("$", "$$")
    if _SYSTEMD_BARE.fullmatch(text):
        return text
    return f'"{text.translate(_SYSTEMD_ESCAPES)}"'


def systemd_command(words: list[str]) -> str:
    """An Exec*= command line. systemd takes the program path literally and refuses odd characters
    in it, so an unusual path is run through `/bin/sh -c 'exec "$0" "$@"'` instead."""
    program, args = words[0], list(words[1:])
    if not (_SYSTEMD_BARE.fullmatch(program) and program.startswith("/") and posixpath.normpath(program) == program):
        program, args = "/bin/sh", ["-c", 'exec "$0" "$@"', program, *args]
    return " ".join([program.replace("%", "%%"), *(systemd_quote(arg) for arg in args)])


def systemd_raw(text: str) -> str:
    """A setting systemd takes as raw text, unquoted (WorkingDirectory=, Description=): `%` specifiers
    escaped. A control character would end or corrupt the line: ValueError."""
    if _CONTROL_CHARACTER.search(text):
        raise ValueError(f"a systemd setting cannot hold control characters: {text!r}")
    return text.replace("%", "%%")


_SUPERVISOR_BARE = re.compile(r"[A-Za-z0-9_@%+=:,./-]+")
_INI_BREAKS = "\n\r\0"
_INI_COMMENT = re.compile(r"\s[;#]")  # a comment marker after whitespace


def supervisor_value(text: str) -> str:
    """A value of supervisord's `environment=` (KEY=<this>,...), `%` doubled for its %(name)s
    expansion. Its parser (non-POSIX shlex) knows no escapes, and its INI reader cuts a line at a
    `;` or `#` after whitespace, so values holding line breaks, both quote characters, a quote at
    either end, or such a comment marker raise ValueError (pass those through `command=` instead)."""
    quote = '"' if '"' not in text else "'"
    if (
        any(ch in text for ch in _INI_BREAKS)
        or quote in text
        or _INI_COMMENT.search(text)
        or (text and (text[0] in "'\"" or text[-1] in "'\""))
    ):
        raise ValueError(f"supervisord's environment= cannot hold {text!r}")
    return quote + text.replace("%", "%%") + quote


def supervisor_command(words: list[str]) -> str:
    """supervisord's `command=`: POSIX shell words (it splits with shlex), single-quoted when needed,
    `%` doubled. Its INI reader takes a `;` or `#` after whitespace for a comment, so those are escaped
    outside the quotes; it strips the lines of a value, so a line break is written as a continuation
    line with the quotes closed around it. It reads a carriage return as a line break and no argument
    can hold NUL: ValueError."""
    quoted = []
    for word in words:
        if "\r" in word or "\0" in word:
            raise ValueError(f"supervisord's command= cannot hold a carriage return or NUL: {word!r}")
        if _SUPERVISOR_BARE.fullmatch(word):
            quoted.append(word)
            continue
        inner = re.sub(r"(\s)([;#])", r"\1'\\\2'", word.replace("'", "'\\''"))
        quoted.append("'" + inner.replace("\n", "''\n  ''") + "'")
    return " ".join(quoted).replace("%", "%%")
