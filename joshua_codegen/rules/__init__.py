"""Registry of every diagnostic code: its rule module, its explanation, and the engine that runs rules.

Code scheme (stable: a code keeps its meaning forever; E = error, the build refuses;
W = warning, reported while the build goes on):

    E001-E009   loading: syntax, unknown fields, bad values, repeated fields, file root, reading
    E010-E012   `--set KEY=VALUE` overrides
    E1xx, W1xx  robot and node fields: names, required fields per node type, values that apply
    E2xx, W2xx  topics, message types and node names
    E3xx        QoS
    E4xx        hardware: serial ports, cameras, servo ids, baud rates, joint names
    E5xx, W5xx  modes and process settings
    E6xx        fleet files: names, addresses, ROS domains and rollout settings of a fleet's robots

Each code lives in one module `rules/<code>_<name>.py` with `CODE`, `NAME`, `SEVERITY`, `STAGE`
and a docstring under the headings "What it checks", "Why it matters" and "Example". A docstring
names node types through placeholders that the module's `TYPE_LISTS` fills from the registry
(joshua_codegen/type_lists.py), never by a list written out.
`STAGE` says who reports it: "load" (the loader), "override" (the `--set` parser), "check" (the
module's own `check(ctx)`, which yields `Finding`s) or "plan" (also `check(ctx)`, reading the planned
model `ctx.robot`; run only when nothing before found an error, since only a valid description plans)
or "fleet" (`check(ctx)` on a fleet file, ctx being fleet/check.py's FleetContext).

When loading found problems inside some nodes only, the "check" rules still run on the rest: those
nodes are left out of `ctx.nodes` and of the topic index. A rule that concludes from something being
absent ("nobody publishes it", "no INFERENCE node") sets `NEEDS_EVERY_NODE = True` and is skipped then,
since the unknown node might be what is missing.
"""

from __future__ import annotations

import importlib
import pkgutil
import re
from functools import cache
from types import ModuleType

from joshua_codegen import type_lists
from joshua_codegen.diagnostics import Diagnostic, Related
from joshua_codegen.rules.context import Finding, RuleContext

RULE_MODULE_NAME = re.compile(r"^[ew]\d{3}_[a-z0-9_]+$")
HEADINGS = ("What it checks", "Why it matters", "Example")


@cache
def _registry() -> dict[str, ModuleType]:
    rules = {}
    for info in pkgutil.iter_modules(__path__):
        if RULE_MODULE_NAME.match(info.name):
            module = importlib.import_module(f"{__name__}.{info.name}")
            rules[module.CODE] = module
    return dict(sorted(rules.items()))


def all_rules() -> list[ModuleType]:
    """Every rule module, sorted by code."""
    return list(_registry().values())


def rule(code: str) -> ModuleType | None:
    return _registry().get(code.strip().upper())


def explain(code: str) -> str | None:
    """`joshuac explain CODE`: the rule's docstring and severity, or None for an unknown code."""
    module = rule(code)
    if module is None:
        return None
    title, _, body = docstring(module).partition("\n")
    return f"{title}\nSeverity: {module.SEVERITY}\n{body}\n"


def docstring(module: ModuleType) -> str:
    """The rule's docstring with its node-type placeholders filled from the registry."""
    return type_lists.render((module.__doc__ or "").strip(), getattr(module, "TYPE_LISTS", {}))


def summaries() -> list[str]:
    """One line per code, sorted: `E301 reliability-incompatible  error    <what it reports>`."""
    lines = []
    for module in all_rules():
        title = docstring(module).partition("\n")[0]
        what = title.partition(": ")[2]
        lines.append(f"{module.CODE} {module.NAME:<40} {module.SEVERITY:<8} {what}".rstrip())
    return lines


def run_rules(context: RuleContext, stage: str = "check") -> list[Diagnostic]:
    """Every finding of every rule of a stage ("check" or "plan"), as diagnostics (unsorted)."""
    diagnostics = []
    for module in all_rules():
        if module.STAGE != stage:
            continue
        if context.unknown_nodes and getattr(module, "NEEDS_EVERY_NODE", False):
            continue
        for finding in module.check(context):
            diagnostics.append(_diagnostic(module, finding, context))
    return diagnostics


def _diagnostic(module: ModuleType, finding: Finding, context: RuleContext) -> Diagnostic:
    where = context.source.locate(finding.at)
    related = []
    for path, message in finding.related:
        other = context.source.locate(path)
        related.append(Related(other.path, other.line, other.column, message))
    line, column, end_line, end_column = where.line, where.column, where.end_line, where.end_column
    if finding.column is not None:
        column, end_line, end_column = finding.column, line, finding.end_column
    return Diagnostic(
        where.path, line, column, module.CODE, module.SEVERITY, finding.message, end_line, end_column, tuple(related)
    )
