"""The dashboard's and the fleet view's API, written once in api.schema.json: its version and the names it fixes.

The document (JSON Schema 2020-12) holds every JSON reply of the HTTP routes (`routes`), every
Server-Sent Event of /api/events (`events`) and the shapes they share (`$defs`). The server's code
takes stream kinds, node actions and event names from here; web/src/types.ts is rendered from it
(api_typescript.py); the tests check the servers' replies against it.
"""

import json
from pathlib import Path

SCHEMA_PATH = Path(__file__).resolve().parent / "api.schema.json"
SCHEMA: dict = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
VERSION: str = SCHEMA["version"]
# The Server-Sent Events of /api/events, by name.
EVENT_KINDS: tuple[str, ...] = tuple(SCHEMA["events"])


def enum(definition: str) -> tuple[str, ...]:
    """The values of the enumeration `definition` of $defs (StreamKind, NodeAction, ...)."""
    return tuple(SCHEMA["$defs"][definition]["enum"])


def named(definition: str, value: str) -> str:
    """`value`, checked to be one of the enumeration `definition`: a name the code uses stays the schema's."""
    if value not in enum(definition):
        raise ValueError(f"{value!r} is not a {definition} of {SCHEMA_PATH.name} ({', '.join(enum(definition))})")
    return value


def event_kind(value: str) -> str:
    """`value`, checked to be an event of /api/events."""
    if value not in EVENT_KINDS:
        raise ValueError(f"{value!r} is not an event of {SCHEMA_PATH.name} ({', '.join(EVENT_KINDS)})")
    return value


def reply_schema(route: str, status: int) -> dict | None:
    """The schema of `route`'s reply with HTTP `status` (`"GET /api/robot"`, 200): the route's own, its
    `default` for a status it does not name, the reply every route may give, or None."""
    replies = SCHEMA["routes"][route]["replies"]
    return replies.get(str(status)) or replies.get("default") or SCHEMA["every_route"]["replies"].get(str(status))
