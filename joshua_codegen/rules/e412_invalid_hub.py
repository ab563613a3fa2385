"""E412 invalid-hub: a base's hub is neither a Bluetooth address nor a hub name.

What it checks:
    `hub` is either a Bluetooth address of six two-digit hex bytes (`AA:BB:CC:DD:EE:FF`) or a hub
    name: no ":" in it, no space at either end, and at most 29 bytes (what one BLE advertising
    packet carries).

Why it matters:
    A half-typed address is taken for a name, and no hub advertises it: the base would scan and
    fail at start-up. A name with a stray space never matches the hub's either.

Example:
    node {
      type: DIFF_DRIVE_BASE
      hub: "90:84:2B:4A:3B"      # error: hub "90:84:2B:4A:3B" is not a Bluetooth address (AA:BB:CC:DD:EE:FF)
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.devices import BLE_ADDRESS, BLE_NAME_MAX_BYTES

CODE = "E412"
NAME = "invalid-hub"
SEVERITY = ERROR
STAGE = "check"


def problem(hub: str) -> str | None:
    if ":" in hub:
        return None if BLE_ADDRESS.fullmatch(hub) else "is not a Bluetooth address (AA:BB:CC:DD:EE:FF)"
    if hub != hub.strip():
        return "has a space at its start or end"
    if len(hub.encode()) > BLE_NAME_MAX_BYTES:
        return f"is longer than the {BLE_NAME_MAX_BYTES} bytes a hub name can have"
    return None


def check(ctx):
    for view in ctx.nodes:
        hub = view.node.hub
        found = problem(hub) if hub else None
        if found:
            yield Finding(view.at("hub"), f'hub "{hub}" {found}')
