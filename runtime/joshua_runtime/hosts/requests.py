"""Requests to a host's agent, from its local socket or from another host over Zenoh: bounded, checked, one line.

A request is a control-socket request of the supervisor (`{"command": "status"}`, `{"command": "restart",
"node": NAME}`, ...) with one more field: `"host": NAME` (whose supervisor answers; default this host's) or
`"all_hosts": true` (the status of every host at once). It may also say how long its sender waits for the
answer, `"wait_s": SECONDS` (`ctl` does, for a stop that may take minutes): each agent on the way then waits
RELAY_MARGIN_S less than the one before, so that an answer that came reaches the sender; without it, the
agents' own bounds hold (a dashboard's request). Only what the agent needs is checked here (size, nesting,
JSON, the fields above, the commands relayed, no log following); the supervisor checks the rest itself.
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
WAIT_FIELD = "wait_s"
WAIT_MAX_S = 3600.0  # no answer is worth waiting longer for: a longer wait is a mistake, refused
RELAY_MARGIN_S = 2.0  # each hop gives up this much before the one that asked it
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
    wait_s: float | None = None  # how long the sender waits for the answer (None: it did not say)

    def relayed_wait_s(self) -> float | None:
        """How long the next hop may take to answer: RELAY_MARGIN_S less than the sender waits."""
        return None if self.wait_s is None else max(self.wait_s - RELAY_MARGIN_S, RELAY_MARGIN_S)

    def remote(self) -> dict:
        """The request for another host's agent, with how long it may take."""
        wait_s = self.relayed_wait_s()
        return self.forwarded if wait_s is None else {**self.forwarded, WAIT_FIELD: wait_s}


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
    forwarded = {key: value for key, value in request.items() if key not in (*ROUTING_FIELDS, WAIT_FIELD)}
    return Request("" if all_hosts else host, all_hosts, forwarded, _wait_s(request))


def parse_remote(payload: bytes, own_host: str) -> Request:
    """The request another host's agent sends over Zenoh, for this host's supervisor."""
    request = decode(payload)
    if any(field in request for field in ROUTING_FIELDS):
        raise RequestRefused("bad_request", "a request from another host names no host")
    _check_relayed(request)
    forwarded = {key: value for key, value in request.items() if key != WAIT_FIELD}
    return Request(own_host, False, forwarded, _wait_s(request))


def _wait_s(request: dict) -> float | None:
    wait_s = request.get(WAIT_FIELD)
    if wait_s is None:
        return None
    if isinstance(wait_s, bool) or not isinstance(wait_s, int | float) or not 0 < wait_s <= WAIT_MAX_S:
        raise RequestRefused("bad_request", f"{WAIT_FIELD} must be a number of seconds above 0, at most {WAIT_MAX_S:g}")
    return float(wait_s)


def _check_relayed(request: dict) -> None:
    if request.get("command") not in RELAYED_COMMANDS:
        raise RequestRefused(
            "bad_request",
            f"command {str(request.get('command'))!r:.40} is not relayed (only {', '.join(RELAYED_COMMANDS)})",
        )
    if request.get("follow") is True:
        raise RequestRefused("bad_request", FOLLOW_REFUSED)
