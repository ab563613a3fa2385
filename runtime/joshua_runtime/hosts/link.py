"""The agent's Zenoh session: the router that listens on the control host, a client on every other.

A client opens its session once the router answers (waiting CONNECT_TIMEOUT_MS at a time, in a thread of
its own, so the agent serves its host meanwhile); once open, Zenoh reconnects by itself whenever the link
breaks, and declares its subscriber and queryable again. Multicast scouting is off: the hosts meet only
through the router's endpoint.
"""

import json
import sys
import threading

from joshua_core import control_plane
from joshua_runtime.dashboard.zenoh_link import open_session
from joshua_runtime.errors import SettingsError

# A restart on another host waits for its node's stop cascade (7 s at most by default); answered just before a
# client of the agent's socket (the dashboard, REQUEST_TIMEOUT_S) would give up. A request that says how long its
# sender waits (requests.py, `ctl` stopping a node) is waited for that long instead.
QUERY_TIMEOUT_S = 14.0
RETRY_PAUSE_S = 1.0  # between two attempts to reach the router
MAX_STATUS_BYTES = 64 * 1024  # a status larger than this is dropped, as the fleet view does


class HostsLink:
    """Publishes this host's status, hears the others', serves this host's control queryable and asks the others.

    `on_status(host, status)` is called (from a Zenoh thread) for every status heard; `on_query(query)` for
    every control request to this host (the query is answered later with `answer`).
    """

    def __init__(
        self, robot: str, host: str, endpoint: str, listen: bool, settings: dict, on_status, on_query, out=sys.stdout
    ):
        self.robot, self.host, self.endpoint, self.listen = robot, host, endpoint, listen
        self.settings = settings
        self.on_status, self.on_query = on_status, on_query
        self.session = None
        self.declared = []
        self.closed = threading.Event()
        self.out = out

    def start(self) -> None:
        """The router opens now (a port it cannot listen on is an error); a client keeps trying in the background."""
        if self.listen:
            self._opened(open_session("router", listen=[self.endpoint], settings=self.settings))
            return
        threading.Thread(target=self._connect, name="hosts-link", daemon=True).start()

    def _connect(self) -> None:
        said = False
        while not self.closed.is_set():
            try:
                session = open_session("client", connect=[self.endpoint], settings=self.settings)
            except SettingsError as exc:
                if not said:  # one line; the router may simply not run yet
                    self._say(f"cannot reach the router at {self.endpoint} yet ({exc}); trying again every few seconds")
                    said = True
                self.closed.wait(RETRY_PAUSE_S)
                continue
            self._opened(session)
            self._say(f"joined the other hosts through the router at {self.endpoint}")
            return

    def _say(self, line: str) -> None:
        print(f"{control_plane.process_name(self.host)}: {line}", file=self.out, flush=True)

    def _opened(self, session) -> None:
        if self.closed.is_set():
            session.close()
            return
        self.declared = [
            session.declare_subscriber(control_plane.status_key(self.robot, "*"), self._status),
            session.declare_queryable(control_plane.control_key(self.robot, self.host), self.on_query),
        ]
        self.session = session

    @property
    def connected(self) -> bool:
        return self.session is not None

    def _status(self, sample) -> None:
        host = str(sample.key_expr).split("/")[-2]
        payload = sample.payload.to_bytes()
        try:
            if len(payload) > MAX_STATUS_BYTES:
                raise ValueError("too large")
            status = json.loads(payload)
        except (ValueError, RecursionError):
            status = None  # dropped by the roster, and counted
        self.on_status(host, status)

    def publish(self, status: dict) -> None:
        if self.session is not None:
            self.session.put(control_plane.status_key(self.robot, self.host), json.dumps(status))

    def ask(self, host: str, request: dict, timeout_s: float | None = None) -> dict | None:
        """The reply of `host`'s agent to `request` (blocking, `timeout_s` at most, default QUERY_TIMEOUT_S); None
        when none came."""
        timeout_s = QUERY_TIMEOUT_S if timeout_s is None else timeout_s
        session = self.session
        if session is None:
            return None
        key = control_plane.control_key(self.robot, host)
        for reply in session.get(key, payload=json.dumps(request), timeout=timeout_s):
            if reply.ok is None:
                continue
            try:
                answer = json.loads(reply.ok.payload.to_bytes())
            except (ValueError, RecursionError):
                continue
            if isinstance(answer, dict):
                return answer
        return None

    @staticmethod
    def answer(query, reply: dict) -> None:
        """Answer a control query of another host (from any thread), then let it go."""
        try:
            query.reply(query.key_expr, json.dumps(reply))
        finally:
            query.drop()

    def close(self) -> None:
        self.closed.set()
        session, self.session = self.session, None
        if session is not None:
            for entity in self.declared:
                entity.undeclare()
            session.close()
