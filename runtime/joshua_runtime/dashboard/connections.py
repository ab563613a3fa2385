"""The HTTP server's defence against clients that open connections and never finish a request (slowloris):
a deadline for each request's head, and a cap on connections that closes the longest idle ones first.

uvicorn's own `limit_concurrency` would answer 503 to every new request once idle connections fill the
cap, so a real client would be refused as surely as by the attack; here an idle connection makes room
for a new one instead, and a request in progress (an open event stream) is never cut.
"""

import logging
import resource

from uvicorn.protocols.http.h11_impl import H11Protocol

# A connection must deliver a complete request head this soon after it opens or after its last reply.
HEAD_TIMEOUT_S = 10.0
# An idle kept-alive connection is closed after this many seconds (uvicorn's timeout_keep_alive).
KEEP_ALIVE_S = 5
MAX_CONNECTIONS = 256  # a robot has a few viewers; each browser tab holds one event stream and a few fetches
# The kernel's queue of connections not yet accepted; asyncio also accepts up to this many at once.
ACCEPT_BACKLOG = 512
# File descriptors kept for the rest of the process (ROS, the control socket, files).
FD_RESERVE = 128
MIN_CONNECTIONS = 16

log = logging.getLogger("joshua_runtime.dashboard.connections")


def connection_limit() -> int:
    """MAX_CONNECTIONS, or fewer when the process may open too few files for that many and a full
    accept queue (an accept() that fails for want of descriptors stops every client)."""
    soft, _hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY:
        return MAX_CONNECTIONS
    return max(MIN_CONNECTIONS, min(MAX_CONNECTIONS, soft - FD_RESERVE - ACCEPT_BACKLOG))


def guarded_protocol(max_connections: int) -> type:
    """The HTTP protocol class for uvicorn's `http=` setting, capped at `max_connections`."""
    return type("GuardedH11Protocol", (GuardedH11Protocol,), {"max_connections": max_connections})


class GuardedH11Protocol(H11Protocol):
    """uvicorn's HTTP/1.1 protocol with a head deadline and a connection cap."""

    max_connections = MAX_CONNECTIONS

    def connection_made(self, transport) -> None:
        self.head_deadline = None
        self.idle_since = self.loop.time()
        super().connection_made(transport)
        self._expect_head()
        self._make_room()

    def on_response_complete(self) -> None:
        super().on_response_complete()
        self._expect_head()

    def connection_lost(self, exc) -> None:
        self._cancel_head_deadline()
        super().connection_lost(exc)

    def waiting_for_head(self) -> bool:
        """No request is in progress: the connection is new, or idle after its last reply."""
        return self.cycle is None or self.cycle.response_complete

    def _expect_head(self) -> None:
        self._cancel_head_deadline()
        if self.transport.is_closing() or not self.waiting_for_head():
            return
        self.idle_since = self.loop.time()
        self.head_deadline = self.loop.call_later(HEAD_TIMEOUT_S, self._head_timed_out)

    def _cancel_head_deadline(self) -> None:
        if self.head_deadline is not None:
            self.head_deadline.cancel()
            self.head_deadline = None

    def _head_timed_out(self) -> None:
        self.head_deadline = None
        if self.waiting_for_head() and not self.transport.is_closing():
            self.transport.close()

    def _make_room(self) -> None:
        """Over the cap: close the connections idle the longest; when every other one has a request in
        progress, close this new one."""
        open_connections = [c for c in self.connections if not c.transport.is_closing()]
        excess = len(open_connections) - self.max_connections
        if excess <= 0:
            return
        idle = sorted(
            (c for c in open_connections if c is not self and c.waiting_for_head()), key=lambda c: c.idle_since
        )
        for connection in idle[:excess]:
            connection.transport.close()
        if len(idle) < excess:
            self.transport.close()
            log.warning("%d connections, each with a request in progress: a new one was closed", self.max_connections)
        else:
            log.warning("%d connections: the longest idle were closed to make room", self.max_connections)
