"""Parsing that goes on after a syntax error, so one run reports every problem it can.

Two recoveries, both on `syntax.Parser`:

- A problem inside a field of a top-level block (`node { ... }` in `robot_config`) is collected, and
  parsing resumes at the next line that starts a field of that block. The field becomes a `Broken`
  value, so the loader knows a node was there but not what it says.
- A block never closed (the end of the file is reached inside it) is found by indentation: the block
  whose contents hold a line indented like its own opening line (or left of it) is the one missing its
  `}`. It is reported at its opening line, then the file is parsed again with that block ending before
  that line, to find what else is wrong. When indentation gives no answer, the innermost block still
  open at the end of the file is reported, and parsing stops.
"""

from __future__ import annotations

import bisect

from joshua_codegen.syntax import BlockTrace, GiveUp, Parser
from joshua_codegen.syntax_tree import Document, SyntaxProblem, Token

# Unclosed blocks recovered from in one file before giving up (each costs one more parse).
MAX_UNCLOSED = 16


def parse_recovering(text: str) -> tuple[Document | None, list[SyntaxProblem]]:
    """The syntax tree (None when parsing could not get to the end) and every problem found, in order."""
    implicit: dict[tuple[int, int], int] = {}
    unclosed: list[SyntaxProblem] = []
    while True:
        parser = Parser(text, recover=True, implicit_closes=implicit)
        try:
            document = parser.document()
        except GiveUp:
            return None, unclosed + parser.problems
        except SyntaxProblem as problem:
            found = _unclosed_block(parser, problem) if problem.at_end else None
            if found is None or (found[2] is None and parser.problems):
                # Without indentation to go by, an end of file met while skipping a broken field is
                # only a consequence of that field's problem.
                ending = [] if parser.problems and problem.at_end else [problem]
                return None, unclosed + parser.problems + ending
            report, trace, indent = found
            key = (trace.open.line, trace.open.column)
            if key in implicit:  # closing it by indentation did not help: stop with what is known
                return None, unclosed + parser.problems
            unclosed.append(report)
            if len(implicit) >= MAX_UNCLOSED or indent is None:
                return None, unclosed + parser.problems
            implicit[key] = indent
            continue
        return document, unclosed + parser.problems


def _unclosed_block(parser: Parser, at_end: SyntaxProblem) -> tuple[SyntaxProblem, BlockTrace, int | None] | None:
    """The block most likely missing its closer, its report, and the indentation that ends it (None: unknown)."""
    stream = parser.stream
    starts = stream.line_starts
    positions = [(token.line, token.column) for token in starts]
    best: tuple[tuple, BlockTrace, Token, int] | None = None
    for order, trace in enumerate(parser.traces):
        indent = stream.line_indent.get(trace.name.line, trace.name.column)
        close = trace.close
        stole_close = close is not None and close.text and close.line != trace.open.line and close.column < indent
        if close is not None and not stole_close:
            continue
        first = bisect.bisect_right(positions, (trace.open.line, trace.open.column))
        for token in starts[first:]:
            if close is not None and (token.line, token.column) > (close.line, close.column):
                break
            if token.column <= indent:
                key = ((token.line, token.column), -order)
                if best is None or key < best[0]:
                    best = (key, trace, token, indent)
                break
    if best is not None:
        _, trace, token, indent = best
        notes = ((token.line, token.column, "its contents seem to end before this line, indented like its opening"),)
        return _report(trace, at_end, notes), trace, indent
    still_open = [trace for trace in parser.traces if trace.close is None]
    if not still_open:
        return None
    return _report(still_open[-1], at_end, ()), still_open[-1], None


def _report(trace: BlockTrace, at_end: SyntaxProblem, notes: tuple) -> SyntaxProblem:
    name, open_token = trace.name, trace.open
    shown = f"{name.text} {open_token.text}" if name is not open_token else open_token.text
    closer = "}" if open_token.text == "{" else ">"
    notes = notes + ((at_end.line, at_end.column, f'the end of the file is reached without its "{closer}"'),)
    return SyntaxProblem(f'"{shown}" opened here is never closed', name.line, name.column,
                         open_token.end_column if open_token.line == name.line else name.end_column, notes=notes)
