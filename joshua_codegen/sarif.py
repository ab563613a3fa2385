"""Diagnostics as SARIF 2.1.0 (`--format sarif`), the log format code-scanning services read.

One run of one tool, `joshuac`, whose driver lists one rule per diagnostic code (every code, whether
reported or not), each with the text of `joshuac explain CODE` as its help. Results refer to their rule
by id and index. Regions count columns in Unicode code points as joshuac does (`columnKind`), and
`endColumn` is one past the last character, as in SARIF. File paths become relative URI references;
a problem of a `--set` override has no file, so its result has no location but says where in its message.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from urllib.parse import quote

from joshua_codegen.diagnostics import ERROR, Diagnostic, Related, sort_diagnostics
from joshua_codegen.overrides import OVERRIDE_PATH
from joshua_codegen.version import VERSION

SARIF_VERSION = "2.1.0"
SARIF_SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
LEVELS = {ERROR: "error"}  # everything else is a warning


def _level(severity: str) -> str:
    return LEVELS.get(severity, "warning")


def _rules() -> list[dict]:
    from joshua_codegen.rules import all_rules, explain

    rules = []
    for module in all_rules():
        title, _, body = (module.__doc__ or "").strip().partition("\n")
        rules.append(
            {
                "id": module.CODE,
                "name": module.NAME,
                "shortDescription": {"text": title.partition(": ")[2] or title},
                "fullDescription": {"text": body.strip() or title},
                "help": {"text": explain(module.CODE)},
                "defaultConfiguration": {"level": _level(module.SEVERITY)},
            }
        )
    return rules


def _location(path: str, line: int, column: int, end_line: int | None = None, end_column: int | None = None) -> dict:
    region = {"startLine": line, "startColumn": column}
    if end_line is not None and end_column is not None:
        region["endLine"] = end_line
        region["endColumn"] = end_column
    return {"physicalLocation": {"artifactLocation": {"uri": quote(path)}, "region": region}}


def _related(notes: tuple[Related, ...]) -> list[dict]:
    located = []
    for index, note in enumerate(notes):
        if note.path == OVERRIDE_PATH:
            continue
        location = _location(note.path, note.line, note.column)
        located.append({"id": index, **location, "message": {"text": note.message}})
    return located


def _result(d: Diagnostic, rule_index: dict[str, int]) -> dict:
    result = {"ruleId": d.code, "level": _level(d.severity), "message": {"text": d.message}}
    if d.code in rule_index:
        result["ruleIndex"] = rule_index[d.code]
    if d.path == OVERRIDE_PATH:
        result["message"]["text"] = f"{d.message} (in --set, item {d.line})"
    else:
        result["locations"] = [_location(d.path, d.line, d.column, d.end_line, d.end_column)]
    related = _related(d.related)
    if related:
        result["relatedLocations"] = related
    return result


def format_sarif(diags: Iterable[Diagnostic]) -> str:
    """The SARIF log of the diagnostics, sorted as every form is, ending with a newline."""
    rules = _rules()
    rule_index = {rule["id"]: index for index, rule in enumerate(rules)}
    document = {
        "$schema": SARIF_SCHEMA,
        "version": SARIF_VERSION,
        "runs": [
            {
                "tool": {"driver": {"name": "joshuac", "version": VERSION, "rules": rules}},
                "columnKind": "unicodeCodePoints",
                "results": [_result(d, rule_index) for d in sort_diagnostics(diags)],
            }
        ],
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"
