"""Requests to a host's agent, from its local socket or from another host over Zenoh: bounded, checked, one line.

A request is a control-socket request of the supervisor (`{"command": "status"}`, `{"command": "restart",
"node": NAME}`, ...) with one more field: `"host": NAME` (whose supervisor answers; default this host's) or
`"all_hosts": true` (the status of every host at once). Only what the agent needs is checked here (size,
nesting, JSON, the two fields, the commands relayed, no log following); the supervisor checks the rest itself.
"""

import json
import re
from dataclasses import dataclass

# The supervisor's own limits on a request line (its control_request.py): the agent forwards nothing longer.
REQUEST_LIMIT_BYTES = 4096
REQUEST_DEPTH = 4
JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
JSON_BRACKET = re.compile(r"[\[\]{}]")
ROUTING_FIELDS = ("host", "all_hosts")
# What one host may ask of another's supervisor: its status, and a node's restart, stop, start and log. A reload
# names a build on the host that runs it, and stays there.
RELAYED_COMMANDS = ("status", "restart", "stop", "start", "logs")
FOLLOW_REFUSED = "logs -f follows a node through its host's control socket only: run `supervisor.py ctl logs -f` there"


class RequestRefused(Exception):
    """Why a request was refused: a refusal `kind` (the supervisor's kinds, and `unreachable`) and one line."""

    def __init__(self, kind: str, error: str):
        super().__init__(error)
        self.kind = kind
        self.error = error

    def reply(self) -> dict:
        return refusal(self.kind, self.error)


def refusal(kind: str, error: str) -> dict:
    return {"ok": False, "kind": kind, "error": error}


@dataclass(frozen=True)
class Request:
    host: str  # whose supervisor answers ("" with all_hosts)
    all_hosts: bool
    forwarded: dict  # the request as that supervisor takes it


def _depth(text: str) -> int:
    depth = deepest = 0
    for bracket in JSON_BRACKET.findall(JSON_STRING.sub('""', text)):
        depth += 1 if bracket in "[{" else -1
        deepest = max(deepest, depth)
    return deepest


def decode(line: bytes) -> dict:
    """The JSON object of one request line; RequestRefused (bad_request) when it is not one within the limits."""
    if len(line) > REQUEST_LIMIT_BYTES:
        raise RequestRefused("bad_request", f"request longer than {REQUEST_LIMIT_BYTES} bytes")
    try:
        text = line.decode("utf-8")
    except UnicodeDecodeError:
        raise RequestRefused("bad_request", "a request is one JSON object in UTF-8") from None
    if _depth(text) > REQUEST_DEPTH:
        raise RequestRefused("bad_request", f"request nested deeper than {REQUEST_DEPTH} levels")
    try:
        request = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise RequestRefused("bad_request", f"not JSON: {exc}") from None
    if not isinstance(request, dict):
        raise RequestRefused("bad_request", "a request is one JSON object per line")
    return request


def parse(line: bytes, own_host: str, hosts: tuple[str, ...]) -> Request:
    """The checked request of one line given to the agent of `own_host` (of a robot on `hosts`)."""
    request = decode(line)
    host = request.get("host", own_host)
    all_hosts = request.get("all_hosts", False)
    if not isinstance(host, str) or host not in hosts:
        raise RequestRefused("not_found", f"no host {str(host)!r:.60} (hosts: {', '.join(hosts)})")
    if not isinstance(all_hosts, bool):
        raise RequestRefused("bad_request", "all_hosts must be true or false")
    if all_hosts and ("host" in request or request.get("command") != "status"):
        raise RequestRefused("bad_request", "all_hosts goes with the status command alone, without host")
    _check_relayed(request)
    forwarded = {key: value for key, value in request.items() if key not in ROUTING_FIELDS}
    return Request("" if all_hosts else host, all_hosts, forwarded)


def parse_remote(payload: bytes) -> dict:
    """The request another host's agent sends over Zenoh, for this host's supervisor as it is."""
    request = decode(payload)
    if any(field in request for field in ROUTING_FIELDS):
        raise RequestRefused("bad_request", "a request from another host names no host")
    _check_relayed(request)
    return request


def _check_relayed(request: dict) -> None:
    if request.get("command") not in RELAYED_COMMANDS:
        raise RequestRefused(
            "bad_request",
            f"command {str(request.get('command'))!r:.40} is not relayed (only {', '.join(RELAYED_COMMANDS)})",
        )
    if request.get("follow") is True:
        raise RequestRefused("bad_request", FOLLOW_REFUSED)
