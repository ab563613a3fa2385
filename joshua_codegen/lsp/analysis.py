"""One document's check, as `joshuac check` makes it, and the indexes the editor features read from it."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

from joshua_codegen.check import CheckResult, check_text
from joshua_codegen.diagnostics import Diagnostic
from joshua_codegen.positions import Location
from joshua_codegen.rules.context import Endpoint

# Analyses kept per document: the current text and a few before it (undo, redo).
KEPT_ANALYSES = 4


@dataclass
class Analysis:
    path: str
    text: str
    result: CheckResult

    @property
    def diagnostics(self) -> list[Diagnostic]:
        """The diagnostics in this document (an override's are not: the editor has none)."""
        return [d for d in self.result.diagnostics if d.path == self.path]

    @cached_property
    def _endpoints(self) -> tuple[dict[str, list[Endpoint]], list[Endpoint]]:
        context = self.result.context
        if context is None:
            return {}, []
        consumers = [e for role in (context.subscribers, context.readers) for found in role.values() for e in found]
        return context.publishers, consumers

    @property
    def publishers(self) -> dict[str, list[Endpoint]]:
        """Resolved topic -> the nodes publishing it (empty when the description could not be read)."""
        return self._endpoints[0]

    def location(self, endpoint: Endpoint) -> Location:
        return self.result.context.source.locate(endpoint.at)

    def consumer_at(self, line: int, column: int) -> Endpoint | None:
        """The subscription or input topic whose field holds the 1-based position, if any."""
        for endpoint in self._endpoints[1]:
            if endpoint.implied:
                continue
            where = self.location(endpoint)
            if _holds(where, line, column):
                return endpoint
        return None

    @cached_property
    def topics(self) -> list[str]:
        """Every topic the description names, sorted."""
        context = self.result.context
        if context is None:
            return []
        return sorted(set(context.publishers) | set(context.subscribers) | set(context.readers))

    @cached_property
    def node_names(self) -> list[str]:
        context = self.result.context
        return [view.name for view in context.nodes] if context is not None else []


def _holds(where: Location, line: int, column: int) -> bool:
    end_line = where.end_line if where.end_line is not None else where.line
    end_column = where.end_column if where.end_column is not None else where.column + 1
    return (where.line, where.column) <= (line, column) <= (end_line, end_column)


@dataclass
class Analyzer:
    """Checks documents, keeping the last analyses of each so that a text seen before is not checked again."""

    kept: dict[str, list[Analysis]] = field(default_factory=dict)

    def analyze(self, path: str, text: str) -> Analysis:
        history = self.kept.setdefault(path, [])
        for index, analysis in enumerate(history):
            if analysis.text == text:
                history.insert(0, history.pop(index))
                return analysis
        analysis = Analysis(path, text, check_text(path, text))
        history.insert(0, analysis)
        del history[KEPT_ANALYSES:]
        return analysis

    def latest(self, path: str) -> Analysis | None:
        history = self.kept.get(path)
        return history[0] if history else None

    def forget(self, path: str) -> None:
        self.kept.pop(path, None)
