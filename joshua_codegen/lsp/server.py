"""The language server: LSP requests over stdio, answered from `analysis`, `hover`, `completion` and `actions`.

Every open or changed document is checked at once as `joshuac check` checks a file, and its diagnostics
are published; the other requests read the latest check of their document.
"""

from __future__ import annotations

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.workspace import TextDocument

from joshua_codegen.diagnostics import ERROR, Diagnostic
from joshua_codegen.fmt import format_description
from joshua_codegen.lsp.actions import fix_for
from joshua_codegen.lsp.analysis import Analysis, Analyzer
from joshua_codegen.lsp.completion import ENUM_VALUE, FIELD, suggestions
from joshua_codegen.lsp.cursor import cursor_at
from joshua_codegen.lsp.hover import hover_text
from joshua_codegen.lsp.text_positions import Lines
from joshua_codegen.version import VERSION

SOURCE = "joshuac"
COMPLETION_KINDS = {FIELD: types.CompletionItemKind.Field, ENUM_VALUE: types.CompletionItemKind.EnumMember}
TRIGGER_CHARACTERS = [":", '"', " "]


class JoshuacServer(LanguageServer):
    def __init__(self):
        super().__init__(SOURCE, VERSION, text_document_sync_kind=types.TextDocumentSyncKind.Incremental)
        self.analyzer = Analyzer()

    def document(self, uri: str) -> TextDocument:
        return self.workspace.get_text_document(uri)

    def lines(self, document: TextDocument, text: str | None = None) -> Lines:
        return Lines(document.source if text is None else text, document.position_codec.client_num_units)

    def analysis(self, uri: str) -> tuple[TextDocument, Analysis]:
        document = self.document(uri)
        return document, self.analyzer.analyze(_path(document), document.source)

    def publish(self, uri: str) -> None:
        document, analysis = self.analysis(uri)
        lines = self.lines(document)
        diagnostics = [to_lsp(d, lines, uri) for d in analysis.diagnostics]
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, version=document.version, diagnostics=diagnostics)
        )


def _path(document: TextDocument) -> str:
    return document.path or document.uri


def to_lsp(d: Diagnostic, lines: Lines, uri: str) -> types.Diagnostic:
    related = [
        types.DiagnosticRelatedInformation(types.Location(uri, lines.range(r.line, r.column, None, None)), r.message)
        for r in d.related
        if r.path == d.path
    ]
    return types.Diagnostic(
        range=lines.range(d.line, d.column, d.end_line, d.end_column),
        message=d.message,
        severity=types.DiagnosticSeverity.Error if d.severity == ERROR else types.DiagnosticSeverity.Warning,
        code=d.code,
        source=SOURCE,
        related_information=related or None,
    )


server = JoshuacServer()


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: JoshuacServer, params: types.DidOpenTextDocumentParams) -> None:
    ls.publish(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: JoshuacServer, params: types.DidChangeTextDocumentParams) -> None:
    ls.publish(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: JoshuacServer, params: types.DidCloseTextDocumentParams) -> None:
    uri = params.text_document.uri
    ls.analyzer.forget(_path(ls.document(uri)))
    ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


def _position(lines: Lines, position: types.Position) -> tuple[int, int]:
    """joshuac's 1-based line and column of a client position."""
    return position.line + 1, lines.column(position) + 1


@server.feature(types.TEXT_DOCUMENT_HOVER)
def hover(ls: JoshuacServer, params: types.HoverParams) -> types.Hover | None:
    document, analysis = ls.analysis(params.text_document.uri)
    line, column = _position(ls.lines(document), params.position)
    text = hover_text(analysis.text, analysis.diagnostics, line, column)
    if text is None:
        return None
    return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))


@server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=TRIGGER_CHARACTERS))
def completion(ls: JoshuacServer, params: types.CompletionParams) -> types.CompletionList:
    document = ls.document(params.text_document.uri)
    lines = ls.lines(document)
    line, column = _position(lines, params.position)
    cursor = cursor_at(document.source, line, column)
    latest = ls.analyzer.latest(_path(document))  # names used elsewhere: from the last check, not a new one
    topics, nodes = (latest.topics, latest.node_names) if latest is not None else ([], [])
    start = cursor.word.column if cursor.word is not None and cursor.prefix else column
    edit_range = types.Range(lines.position(line, start), params.position)
    items = [
        types.CompletionItem(
            label=s.label,
            kind=COMPLETION_KINDS.get(s.kind, types.CompletionItemKind.Value),
            detail=s.detail,
            documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=s.documentation)
            if s.documentation
            else None,
            text_edit=types.TextEdit(edit_range, s.insert),
        )
        for s in suggestions(cursor, topics, nodes)
    ]
    return types.CompletionList(is_incomplete=False, items=items)


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def definition(ls: JoshuacServer, params: types.DefinitionParams) -> list[types.Location] | None:
    """From a subscribed or read topic to the fields of the nodes that publish it."""
    document, analysis = ls.analysis(params.text_document.uri)
    lines = ls.lines(document)
    line, column = _position(lines, params.position)
    consumer = analysis.consumer_at(line, column)
    if consumer is None:
        return None
    found = []
    for publisher in analysis.publishers.get(consumer.topic, []):
        where = analysis.location(publisher)
        found.append(
            types.Location(
                params.text_document.uri, lines.range(where.line, where.column, where.end_line, where.end_column)
            )
        )
    return found or None


@server.feature(types.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: JoshuacServer, params: types.DocumentFormattingParams) -> list[types.TextEdit] | None:
    """`joshuac fmt` of the document: one edit replacing the whole text, none when it is formatted already."""
    document = ls.document(params.text_document.uri)
    formatted, _problems = format_description(document.source, _path(document))
    if formatted is None or formatted == document.source:
        return None if formatted is None else []
    lines = ls.lines(document)
    end = lines.position(len(lines.lines), len(lines.lines[-1]) + 1)
    return [types.TextEdit(types.Range(types.Position(0, 0), end), formatted)]


@server.feature(
    types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix])
)
def code_action(ls: JoshuacServer, params: types.CodeActionParams) -> list[types.CodeAction] | None:
    """The did-you-mean fixes of the diagnostics in the requested range."""
    document, analysis = ls.analysis(params.text_document.uri)
    lines = ls.lines(document)
    start = _position(lines, params.range.start)
    end = _position(lines, params.range.end)
    actions = []
    for d in analysis.diagnostics:
        d_end = (
            (d.end_line, d.end_column) if d.end_line is not None and d.end_column is not None else (d.line, d.column)
        )
        if d_end < start or (d.line, d.column) > end:
            continue
        fix = fix_for(analysis.text, d)
        if fix is None:
            continue
        edit = types.TextEdit(lines.range(fix.line, fix.column, fix.line, fix.end_column), fix.new_text)
        actions.append(
            types.CodeAction(
                title=fix.title,
                kind=types.CodeActionKind.QuickFix,
                diagnostics=[to_lsp(d, lines, params.text_document.uri)],
                edit=types.WorkspaceEdit(changes={params.text_document.uri: [edit]}),
                is_preferred=True,
            )
        )
    return actions or None


def serve() -> None:
    """Answer LSP requests on standard input and output until the client asks the server to exit."""
    server.start_io()
