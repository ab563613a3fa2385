"""The API's schema (runtime/joshua_runtime/dashboard/api.schema.json) held against what the dashboard and the
fleet view answer in these tests: every JSON reply of a route under /api/ and every event of /api/events."""

import json
import re
from functools import cache

from jsonschema import Draft202012Validator

from joshua_runtime.dashboard.api_schema import EVENT_KINDS, SCHEMA, reply_schema

# (method, path pattern, route) of every route of the schema; `{name}` matches one path segment.
ROUTES = [
    (method, re.compile("^" + re.sub(r"\{[^/}]+\}", "[^/]+", path) + "$"), route)
    for route in SCHEMA["routes"]
    for method, path in [route.split(" ", 1)]
]
JSON_TYPE = "application/json"
MAX_PROBLEMS_SHOWN = 5


@cache
def _validator(reference: str) -> Draft202012Validator:
    """A validator of the definition `reference` (`#/$defs/NAME`) with the whole document around it."""
    return Draft202012Validator({**SCHEMA, "$ref": reference})


def _check(reference: str, value, what: str) -> None:
    problems = sorted(_validator(reference).iter_errors(value), key=lambda error: list(error.absolute_path))
    shown = [f"{'/'.join(map(str, p.absolute_path)) or '(top)'}: {p.message[:300]}" for p in problems]
    assert not problems, f"{what} does not match {reference} of the API schema:\n" + "\n".join(
        shown[:MAX_PROBLEMS_SHOWN]
    )


def route_of(method: str, path: str) -> str | None:
    """The schema's route that `method path` is, or None."""
    return next((route for m, pattern, route in ROUTES if m == method and pattern.match(path)), None)


def check_reply(method: str, path: str, status: int, body) -> None:
    """`body`, the JSON reply with HTTP `status` to `method path`, is what the schema says that route answers."""
    route = route_of(method, path)
    assert route is not None, f"{method} {path} answered JSON but is no route of the API schema"
    schema = reply_schema(route, status)
    assert isinstance(schema, dict), f"the API schema names no {status} reply of {route}"
    _check(schema["$ref"], body, f"the {status} reply to {method} {path}")


def check_event(kind: str, data) -> None:
    """`data`, an event of /api/events named `kind`, is what the schema says that event carries."""
    assert kind in EVENT_KINDS, f"event {kind!r} is not one of the API schema ({', '.join(EVENT_KINDS)})"
    _check(SCHEMA["events"][kind]["$ref"], data, f"the {kind} event")


def checking_replies(client):
    """`client` (Starlette's TestClient, an httpx client) with every JSON reply of /api/ checked against the
    schema as it arrives; the event stream is left to check_event."""

    def check(response) -> None:
        request = response.request
        if not request.url.path.startswith("/api/"):
            return
        if not response.headers.get("content-type", "").startswith(JSON_TYPE):
            return
        response.read()
        check_reply(request.method, request.url.path, response.status_code, json.loads(response.content))

    client.event_hooks["response"].append(check)
    return client
