"""The schema of a robot's status as the fleet view reads it from zenoh: whatever else a peer sends is
dropped before it is kept or shown.

A status is one JSON object of at most MAX_STATUS_BYTES, published under `joshua/<robot>/status` where
<robot> is a robot name (lower-case letters, digits, underscores). Its keys, each optional:
`robot` (the same name), `nodes` (at most MAX_NODES `{"name", "state", "pid", "restarts", "ready",
"since_s"}` of distinct names, as `supervisor.py ctl status --json` prints them), `run` (its `build`, 64 hex
digits, and `built`, a time), `url` (the robot's page: an http or https address, nothing else) and `error` (text).
Other keys are ignored.
"""

from typing import Annotated
from urllib.parse import urlsplit

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, StringConstraints, ValidationError, model_validator

from joshua_core.names import is_robot_name

MAX_STATUS_BYTES = 64 * 1024
MAX_NODES = 256
MAX_NODE_NAME_CHARS = 255
MAX_URL_CHARS = 2048
MAX_ERROR_CHARS = 1024
MAX_COUNT = 2**31 - 1  # pids and restart counts
MAX_TIME_CHARS = 40  # an ISO 8601 time with milliseconds and offset is 29
LINK_SCHEMES = ("http", "https")


def http_link(url: str) -> str:
    """`url` when it is an http(s) address with a host and no space or control character."""
    if any(character.isspace() or not character.isprintable() for character in url):
        raise ValueError("the address holds a space or control character")
    try:
        parts = urlsplit(url)
        host = parts.hostname
    except ValueError as exc:
        raise ValueError("the address cannot be read") from exc
    if parts.scheme not in LINK_SCHEMES or not host:
        raise ValueError("the address is not http:// or https:// with a host")
    return url


def robot_name(text: str) -> str:
    if not is_robot_name(text):
        raise ValueError("not a robot name")
    return text


class _Strict(BaseModel):
    """JSON types as they are (no "1" for 1), unknown keys ignored, never changed once read."""

    model_config = ConfigDict(strict=True, extra="ignore", frozen=True)


class NodeStatus(_Strict):
    name: Annotated[str, StringConstraints(min_length=1, max_length=MAX_NODE_NAME_CHARS)]
    state: Annotated[str, StringConstraints(pattern=r"^[a-z][a-z_]{0,31}$")]
    pid: Annotated[int, Field(ge=1, le=MAX_COUNT)] | None = None
    restarts: Annotated[int, Field(ge=0, le=MAX_COUNT)] = 0
    ready: bool = False
    since_s: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = None


class RunStatus(_Strict):
    """The supervisor's run: which build it runs (the SHA-256 of its stamp) and when that build was written."""

    build: Annotated[str, StringConstraints(pattern=r"^[0-9a-f]{64}$")] | None = None
    built: Annotated[str, StringConstraints(max_length=MAX_TIME_CHARS)] | None = None


class RobotStatus(_Strict):
    robot: Annotated[str, AfterValidator(robot_name)] | None = None
    nodes: Annotated[list[NodeStatus], Field(max_length=MAX_NODES)] = []
    run: RunStatus | None = None
    url: Annotated[str, StringConstraints(max_length=MAX_URL_CHARS), AfterValidator(http_link)] | None = None
    error: Annotated[str, StringConstraints(max_length=MAX_ERROR_CHARS)] | None = None

    @model_validator(mode="after")
    def _node_names_unique(self):
        if len({node.name for node in self.nodes}) != len(self.nodes):
            raise ValueError("two nodes share a name")
        return self


class StatusRejected(ValueError):
    """A status that does not fit the schema; the message says why without repeating what was sent."""


def check_size(size: int) -> None:
    """Refuse a payload of `size` bytes over the limit, before it is copied or parsed."""
    if size > MAX_STATUS_BYTES:
        raise StatusRejected(f"{size} bytes, over the limit of {MAX_STATUS_BYTES}")


def read_status(robot: str, payload: bytes) -> RobotStatus:
    """The status `payload` published under `joshua/<robot>/status`, checked against the schema."""
    if not is_robot_name(robot):
        raise StatusRejected("the key does not name a robot")
    check_size(len(payload))
    try:
        status = RobotStatus.model_validate_json(payload)
    except ValidationError as exc:
        raise StatusRejected(_first_problem(exc)) from None
    if status.robot is not None and status.robot != robot:
        raise StatusRejected("it names another robot")
    return status


def _first_problem(exc: ValidationError) -> str:
    """`nodes.0.state: String should match pattern ...`: where and what, never the value sent."""
    error = exc.errors(include_input=False, include_url=False, include_context=False)[0]
    where = ".".join(str(part) for part in error["loc"])
    return f"{where}: {error['msg']}" if where else error["msg"]
