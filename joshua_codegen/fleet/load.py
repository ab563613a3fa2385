"""A fleet file: telling it from a robot description, and loading it with the source position of every field."""

import re

from joshua_codegen.diagnostics import ERROR, Diagnostic
from joshua_codegen.load import MISSING_ROBOT_CONFIG, load_message
from joshua_codegen.positions import SourceMap
from joshua_core.schema import FleetDescription

# A fleet file's first field (after blank and comment lines) is `fleet_config`.
_FLEET_ROOT = re.compile(r"\A(?:\s|#[^\n]*(?:\n|\Z))*fleet_config\b")
FLEET = ("fleet_config",)


def is_fleet_text(text: str) -> bool:
    return _FLEET_ROOT.match(text) is not None


def robot_path(index: int, *fields) -> tuple:
    """Message path of a fleet robot's field: ("fleet_config", "robot", 2, "address")."""
    return (*FLEET, "robot", index, *fields)


def load_fleet(path: str, text: str) -> tuple[FleetDescription | None, SourceMap, list[Diagnostic]]:
    """(the fleet, or None when it has load errors; source positions; the load diagnostics)."""
    fleet, source, diagnostics = load_message(path, text, FleetDescription)
    if fleet is not None and not fleet.HasField("fleet_config"):
        message = "missing fleet_config { ... }: a fleet file holds one fleet_config block"
        diagnostics.append(Diagnostic(path, 1, 1, MISSING_ROBOT_CONFIG, ERROR, message))
        fleet = None
    return fleet, source, diagnostics
