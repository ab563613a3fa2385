"""Control requests: one bounded JSON line in, a checked request out, or one line saying why not."""

import math
import re

CONTROL_REQUEST_LIMIT = 4096  # longest request line, in bytes (the longest real one is under 200)
CONTROL_REQUEST_DEPTH = 4  # deepest nesting of arrays and objects (a real request has 1)
CONTROL_NUMBER_DIGITS = 20  # longest number literal
CONTROL_LOG_LINES_MAX = 10000  # most lines one `logs` request may ask for
CONTROL_LOG_LINES_DEFAULT = 100
CONTROL_PATH_MAX = 1024  # longest directory path a `reload` may name, in characters (its JSON fits the line)

# The fields each command takes; "node" and "path" are required wherever they are taken, the others have defaults.
CONTROL_COMMANDS = {
    "status": (),
    "restart": ("node",),
    "stop": ("node",),
    "start": ("node",),
    "logs": ("node", "lines", "follow", "all"),
    "reload": ("path",),
}
FIELD_DEFAULTS = {"lines": CONTROL_LOG_LINES_DEFAULT, "follow": False, "all": False}
# The kinds of refusal an error reply names in its "kind" field, for clients that act on them (a web server
# answers them with the HTTP status in the comment).
REFUSAL_KINDS = {
    "bad_request": "the request line is not a request this supervisor takes",  # 400
    "forbidden": "the client is of another user than the supervisor's and not root",  # 403
    "not_found": "no node has that name, or its output is not kept (no log directory)",  # 404
    "conflict": "the node is already in the state asked for, or a stop, restart or reload is under way",  # 409
    "stopping": "the robot is stopping: its nodes are started, stopped and restarted no more",  # 503
    "busy": "too many clients are connected: try again later",  # 503
    "invalid_build": "the build to reload is not one of this robot: another robot's, changed since it was built, "
    "not a build, or built by another joshuac",  # 422
    "preflight": "a node the reload would start cannot start: a device, model, program or entrypoint is missing",  # 422
}
FIELD_RULES = {
    "node": (lambda value: isinstance(value, str), "node must be a string"),
    "lines": (
        lambda value: type(value) is int and 0 <= value <= CONTROL_LOG_LINES_MAX,
        f"lines must be a whole number from 0 to {CONTROL_LOG_LINES_MAX}",
    ),
    "follow": (lambda value: isinstance(value, bool), "follow must be true or false"),
    "all": (lambda value: isinstance(value, bool), "all must be true or false"),
    "path": (
        lambda value: (
            isinstance(value, str) and value.startswith("/") and len(value) <= CONTROL_PATH_MAX and "\0" not in value
        ),
        f"path must be an absolute path of at most {CONTROL_PATH_MAX} characters, without NUL",
    ),
}
JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
JSON_BRACKET = re.compile(r"[\[\]{}]")


class RequestError(ValueError):
    """Why a request line was refused: one line, sent back to the client."""


def refusal(kind: str, error: str) -> dict:
    """The reply that refuses a request: `kind` one of REFUSAL_KINDS, `error` one line saying why."""
    return {"ok": False, "kind": kind, "error": error}


def nesting_depth(text: str) -> int:
    """The deepest nesting of arrays and objects in JSON `text` (brackets inside strings do not count)."""
    depth = deepest = 0
    for bracket in JSON_BRACKET.findall(JSON_STRING.sub('""', text)):
        depth += 1 if bracket in "[{" else -1
        deepest = max(deepest, depth)
    return deepest


def refuse_constant(name: str):
    raise RequestError(f"not a finite number: {name}")


def finite_float(text: str) -> float:
    if len(text) > CONTROL_NUMBER_DIGITS:
        raise RequestError(f"number longer than {CONTROL_NUMBER_DIGITS} characters")
    value = float(text)
    if not math.isfinite(value):
        raise RequestError(f"not a finite number: {text}")
    return value


def bounded_int(text: str) -> int:
    if len(text) > CONTROL_NUMBER_DIGITS:
        raise RequestError(f"number longer than {CONTROL_NUMBER_DIGITS} characters")
    return int(text)


def parse_request(line: bytes) -> dict:
    """The request of one line (without its newline), with every field its command takes; raises RequestError."""
    import json

    try:
        text = line.decode("utf-8")
    except UnicodeDecodeError:
        raise RequestError("a request is one JSON object in UTF-8: this line is not UTF-8") from None
    if nesting_depth(text) > CONTROL_REQUEST_DEPTH:
        raise RequestError(f"request nested deeper than {CONTROL_REQUEST_DEPTH} levels")
    try:
        request = json.loads(text, parse_constant=refuse_constant, parse_float=finite_float, parse_int=bounded_int)
    except RequestError:
        raise
    except (ValueError, RecursionError) as exc:
        raise RequestError(f"not JSON: {exc}") from None
    if not isinstance(request, dict):
        raise RequestError(f"a request is one JSON object per line, not {type(request).__name__}")
    command = request.get("command")
    if not isinstance(command, str):
        raise RequestError(f"command must be one of {', '.join(CONTROL_COMMANDS)}")
    if command not in CONTROL_COMMANDS:
        raise RequestError(f"unknown command {command!r:.60} ({', '.join(CONTROL_COMMANDS)})")
    fields = CONTROL_COMMANDS[command]
    for key in request:
        if key != "command" and key not in fields:
            raise RequestError(f"unknown field {key!r:.60} for {command} (it takes {', '.join(fields) or 'none'})")
    checked = {"command": command}
    for field in fields:
        if field not in request and field not in FIELD_DEFAULTS:
            raise RequestError(f"{command} needs a {field}")
        value = request.get(field, FIELD_DEFAULTS.get(field))
        valid, rule = FIELD_RULES[field]
        if not valid(value):
            raise RequestError(rule)
        checked[field] = value
    return checked
