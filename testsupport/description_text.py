"""Pieces of a robot description's text format written by tests."""


def quoted(text: str) -> str:
    """A text-format string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
