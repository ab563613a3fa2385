"""Every host's status as this host's agent knows it, and the robot's status it makes of them.

A host counts as reachable while its status is newer than HOST_SILENT_AFTER_S (agents publish theirs every
STATUS_PERIOD_S). The processes of a host that is not are listed with state `unknown` (no pid, not ready):
nothing is known of them, and they are never shown running. A process on a reachable host that subscribes to a
topic published only on hosts that are not is listed as `waiting`, with those hosts in `waiting_for`.
"""

import math
from dataclasses import dataclass

STATUS_PERIOD_S = 1.0  # how often each agent publishes its host's status
HOST_SILENT_AFTER_S = 3.0  # a host not heard from for this long is unreachable
UNKNOWN, WAITING, RUNNING = "unknown", "waiting", "running"
MAX_NODES = 256
MAX_STATE_CHARS = 32
NODE_FIELDS = ("name", "state", "pid", "restarts", "manual_restarts", "ready", "since_s")


@dataclass(frozen=True)
class HostPlan:
    name: str
    address: str
    processes: tuple[str, ...]


@dataclass(frozen=True)
class Placement:
    """What the manifest says about the hosts: each with its processes, and who publishes what each reads."""

    robot: str
    host: str  # this agent's host
    hosts: tuple[HostPlan, ...]
    inputs: dict  # process -> {topic: (publishing processes)} for each topic it subscribes to

    @classmethod
    def from_manifest(cls, manifest: dict) -> "Placement":
        hosts = tuple(HostPlan(h["name"], h["address"], tuple(h["processes"])) for h in manifest["hosts"])
        inputs: dict[str, dict[str, tuple[str, ...]]] = {}
        for topic in manifest["topics"]:
            publishers = tuple(endpoint["node"] for endpoint in topic["publishers"])
            for endpoint in topic["subscribers"]:
                inputs.setdefault(endpoint["node"], {})[topic["name"]] = publishers
        return cls(manifest["robot"]["name"], manifest["host"], hosts, inputs)

    @property
    def host_names(self) -> tuple[str, ...]:
        return tuple(host.name for host in self.hosts)

    def host_of(self, process: str) -> str | None:
        return next((host.name for host in self.hosts if process in host.processes), None)


def checked_status(status, host: HostPlan) -> dict | None:
    """`status` when it is a supervisor status of `host` (its processes, each with fields of the right types)."""
    if not isinstance(status, dict) or not isinstance(status.get("nodes"), list) or len(status["nodes"]) > MAX_NODES:
        return None
    for node in status["nodes"]:
        if not (
            isinstance(node, dict)
            and node.get("name") in host.processes
            and isinstance(node.get("state"), str)
            and len(node["state"]) <= MAX_STATE_CHARS
            and (node.get("pid") is None or type(node.get("pid")) is int)
            and type(node.get("restarts")) is int
            and type(node.get("manual_restarts", 0)) is int
            and isinstance(node.get("ready"), bool)
            and isinstance(node.get("since_s"), (int, float))
            and math.isfinite(node["since_s"])
        ):
            return None
    return status


class Roster:
    """The last status heard of each host, with when; `aggregate(now)` makes the robot's status of them."""

    def __init__(self, placement: Placement, linked: bool):
        self.placement = placement
        self.linked = linked  # whether the other hosts can be heard at all (`control { }`)
        self.heard: dict[str, tuple[dict, float]] = {}  # host -> (status, monotonic time it came)
        self.errors: dict[str, str] = {}  # host -> why its last status is missing (this host: the supervisor)

    def record(self, host: str, status: dict, now: float) -> bool:
        """Keep `status` of `host` when it checks; False when it was dropped."""
        plan = next((h for h in self.placement.hosts if h.name == host), None)
        if plan is None or checked_status(status, plan) is None:
            return False
        self.heard[host] = (status, now)
        self.errors.pop(host, None)
        return True

    def record_error(self, host: str, error: str) -> None:
        """This host's supervisor did not answer: its processes are unknown from now on."""
        self.heard.pop(host, None)
        self.errors[host] = error

    def reachable(self, host: str, now: float) -> bool:
        heard = self.heard.get(host)
        return heard is not None and now - heard[1] <= HOST_SILENT_AFTER_S

    def aggregate(self, now: float) -> dict:
        """{"robot", "host", "hosts": [{"name", "address", "reachable", "last_seen_s", "detail", "run",
        "discovery"}], "nodes": [the supervisors' node fields, with "host" (and "waiting_for" when waiting)]}."""
        hosts, nodes = [], []
        for plan in self.placement.hosts:
            reachable = self.reachable(plan.name, now)
            status, heard_at = self.heard.get(plan.name, ({}, None))
            hosts.append(
                {
                    "name": plan.name,
                    "address": plan.address,
                    "reachable": reachable,
                    "last_seen_s": None if heard_at is None else round(now - heard_at, 3),
                    "detail": self.silence(plan.name, now),
                    "run": status.get("run") if reachable else None,
                    "discovery": status.get("discovery") if reachable else None,
                }
            )
            if reachable:
                nodes += [
                    {**{key: node.get(key) for key in NODE_FIELDS}, "host": plan.name} for node in status["nodes"]
                ]
            else:
                last = {node["name"]: node for node in status.get("nodes", [])}
                nodes += [self._unknown(name, plan.name, heard_at, now, last.get(name, {})) for name in plan.processes]
        silent = {host["name"] for host in hosts if not host["reachable"]}
        for node in nodes:
            waiting_for = self._waiting_for(node["name"], silent)
            if waiting_for and node["state"] == RUNNING:
                node.update(state=WAITING, waiting_for=waiting_for)
        return {"robot": self.placement.robot, "host": self.placement.host, "hosts": hosts, "nodes": nodes}

    def silence(self, host: str, now: float) -> str:
        """Why `host` is not reachable ("" when it is)."""
        if self.reachable(host, now):
            return ""
        heard_at = self.heard.get(host, (None, None))[1]
        if host in self.errors:
            return self.errors[host]
        if host != self.placement.host and not self.linked:
            return "no control plane: the description has no `control { }` block"
        if heard_at is None:
            return "not heard from yet"
        return f"not heard from for {now - heard_at:.1f} s"

    def _unknown(self, name: str, host: str, heard_at: float | None, now: float, last: dict) -> dict:
        """A process of a silent host: state unknown since its host was last heard from, its restart counts as
        they were then."""
        since = None if heard_at is None else round(now - heard_at, 3)
        return {
            "name": name,
            "state": UNKNOWN,
            "pid": None,
            "restarts": last.get("restarts", 0),
            "manual_restarts": last.get("manual_restarts", 0),
            "ready": False,
            "since_s": since,
            "host": host,
        }

    def _waiting_for(self, process: str, silent: set[str]) -> list[str]:
        """The silent hosts that alone publish a topic `process` reads."""
        waiting = set()
        for publishers in self.placement.inputs.get(process, {}).values():
            hosts = {self.placement.host_of(publisher) for publisher in publishers} - {None}
            if hosts and hosts <= silent:
                waiting |= hosts
        return sorted(waiting)
