"""What this host's agent last said of the Discovery Server (one of a robot on several hosts), for `ctl status`."""

from joshua_codegen.supervisor.robot import ROBOT

# The sd_notify field through which a host's agent reports the server: `reachable` or `unreachable`.
DISCOVERY_FIELD = "DISCOVERY_SERVER"
DISCOVERY_STATES = {"reachable": True, "unreachable": False}


class DiscoveryReport:
    """The server's reachability as the host's agent last reported it (a DISCOVERY_SERVER= notification, with
    its STATUS= line), and since when; unknown while no running agent has said anything."""

    def __init__(self, server: str):
        self.server = server
        self.reporter = None  # the node (the host's agent) whose report this is
        self.reachable = None
        self.detail = "not reported yet (the host's agent probes the server)"
        self.changed_at = None

    @classmethod
    def of_robot(cls):
        """The report of this host's Discovery Server, or None when the robot has none."""
        server = ROBOT.get("discovery_server")
        return cls(server) if server else None

    def record(self, node, state: str, detail: str, now: float) -> None:
        reachable = DISCOVERY_STATES.get(state)
        if reachable != self.reachable or self.changed_at is None:
            self.changed_at = now
        self.reporter, self.reachable, self.detail = node, reachable, detail

    def forget(self, node, now: float) -> None:
        """The reporting agent ended: nothing is known until it runs and reports again."""
        if node is self.reporter:
            self.reporter, self.reachable, self.changed_at = None, None, now
            self.detail = f"{node.name} ended: the server is not watched until it runs again"

    def as_dict(self, now: float) -> dict:
        """{"server", "reachable" (true, false, or null when unknown), "since_s" (in that state), "detail"}."""
        since = None if self.changed_at is None else round(now - self.changed_at, 3)
        return {"server": self.server, "reachable": self.reachable, "since_s": since, "detail": self.detail}
