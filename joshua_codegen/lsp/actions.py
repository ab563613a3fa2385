"""Quick fixes: the replacement a diagnostic suggests with `did you mean "X"?`, applied to the text it points at."""

from __future__ import annotations

import re
from dataclasses import dataclass

from joshua_codegen.diagnostics import Diagnostic
from joshua_codegen.syntax import tokens
from joshua_codegen.syntax_tree import QUOTES

SUGGESTION = re.compile(r'did you mean "((?:[^"\\]|\\.)*)"\?')


@dataclass(frozen=True)
class Fix:
    diagnostic: Diagnostic
    title: str
    line: int  # 1-based position of the replaced token
    column: int
    end_column: int
    new_text: str


def _last_word(text: str, d: Diagnostic) -> tuple[str, int, int] | None:
    """(text, line, column) of the last value or name token inside the diagnostic's range."""
    end = (d.end_line, d.end_column) if d.end_line is not None and d.end_column is not None else None
    found = None
    for token, line, column in tokens(text):
        if (line, column) < (d.line, d.column):
            continue
        if end is None:
            if (line, column) != (d.line, d.column):
                break
        elif (line, column + len(token)) > end:
            break
        if token[:1] in QUOTES or token[:1].isalnum() or token[:1] in "_+-./":
            found = (token, line, column)
    return found


def fix_for(text: str, d: Diagnostic) -> Fix | None:
    """The fix a diagnostic suggests, or None when it suggests none."""
    match = SUGGESTION.search(d.message)
    if match is None:
        return None
    word = _last_word(text, d)
    if word is None:
        return None
    token, line, column = word
    suggestion = match.group(1).replace('\\"', '"')
    if token[:1] in QUOTES:
        new_text = '"' + suggestion.replace("\\", "\\\\").replace('"', '\\"') + '"'
    else:
        new_text = suggestion
    if new_text == token:
        return None
    return Fix(d, f"Replace {token} with {new_text}", line, column, column + len(token), new_text)
