"""Parsing that goes on after a syntax error, so one run reports every problem it can.

Two recoveries, both on `syntax.Parser`:

- A problem inside a field of a top-level block (`node { ... }` in `robot_config`) is collected, and
  parsing resumes at the next line that starts a field of that block. The field becomes a `Broken`
  value, so the loader knows a node was there but not what it says.
- A block never closed (the end of the file is reached inside it) is found by indentation: the block
  whose contents hold a line indented like its own opening line (or left of it) is the one missing its
  `}`. The file is parsed again with every such block ending before that line (until no new one
  shows), and each is reported at its opening line. When indentation gives no answer, the innermost
  block still open at the end of the file is reported, and parsing stops.
"""

from __future__ import annotations

import bisect

from joshua_codegen.syntax import BlockTrace, GiveUp, Parser
from joshua_codegen.syntax_tree import Document, SyntaxProblem

# Parses of one file while unclosed blocks are being found (each finds all it can see).
MAX_ROUNDS = 8


def parse_recovering(text: str) -> tuple[Document | None, list[SyntaxProblem]]:
    """The syntax tree (None when parsing could not get to the end) and every problem found."""
    implicit: dict[tuple[int, int], int] = {}
    end: SyntaxProblem | None = None
    for _ in range(MAX_ROUNDS):
        parser = Parser(text, recover=True, implicit_closes=implicit)
        try:
            document = parser.document()
        except GiveUp:
            return None, _closed_by_indentation(parser, end) + parser.problems
        except SyntaxProblem as problem:
            closed = _closed_by_indentation(parser, end or problem)
            if not problem.at_end:
                return None, closed + parser.problems + [problem]
            end = end or problem
            new = {key: indent for key, indent in _unclosed_candidates(parser).items() if key not in implicit}
            if new:
                implicit.update(new)
                continue
            if parser.problems:
                # Without indentation to go by, an end of file met while skipping a broken field is
                # only a consequence of that field's problem.
                return None, closed + parser.problems
            still_open = [trace for trace in parser.traces if trace.close is None]
            innermost = [_report(still_open[-1], end, ())] if still_open else [problem]
            return None, closed + innermost
        return document, _closed_by_indentation(parser, end) + parser.problems
    return None, _closed_by_indentation(parser, end) + parser.problems


def _unclosed_candidates(parser: Parser) -> dict[tuple[int, int], int]:
    """Blocks still open at the end, or closed left of their opening line, whose contents hold a line
    indented like their opening line (or left of it): opening position -> that indentation."""
    stream = parser.stream
    starts = stream.line_starts
    positions = [(token.line, token.column) for token in starts]
    found = {}
    for trace in parser.traces:
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
                found[(trace.open.line, trace.open.column)] = indent
                break
    return found


def _closed_by_indentation(parser: Parser, end: SyntaxProblem | None) -> list[SyntaxProblem]:
    """A report for every block the parse closed by indentation."""
    reports = []
    for trace in parser.traces:
        if trace.close is not None and not trace.close.text and trace.ended_before is not None:
            token = trace.ended_before
            notes = (
                (token.line, token.column, "its contents seem to end before this line, indented like its opening"),
            )
            reports.append(_report(trace, end, notes))
    return reports


def _report(trace: BlockTrace, end: SyntaxProblem | None, notes: tuple) -> SyntaxProblem:
    name, open_token = trace.name, trace.open
    shown = f"{name.text} {open_token.text}" if name is not open_token else open_token.text
    closer = "}" if open_token.text == "{" else ">"
    if end is not None:
        notes = notes + ((end.line, end.column, f'the end of the file is reached without its "{closer}"'),)
    return SyntaxProblem(
        f'"{shown}" opened here is never closed',
        name.line,
        name.column,
        open_token.end_column if open_token.line == name.line else name.end_column,
        notes=notes,
    )
