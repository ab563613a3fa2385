"""One client of the control socket: request lines in, reply lines out through a bounded buffer, never blocking."""

import socket
import time

from joshua_codegen.supervisor.control_request import CONTROL_REQUEST_LIMIT, refusal

CONTROL_RECEIVE_BYTES = 65536  # read at most this much of a client's requests at a time
CONTROL_REQUESTS_PER_TURN = 8  # request lines of one client handled before the loop turns to other work
# Replies a client may leave unread in the supervisor, beyond what the kernel's socket buffer holds: past
# either limit the client is dropped. The largest single reply (`logs` of 1 MiB of output, escaped) fits.
CONTROL_OUTPUT_LIMIT_BYTES = 8 * 1024 * 1024  # per client
CONTROL_OUTPUT_TOTAL_BYTES = 64 * 1024 * 1024  # all clients together


class ControlConnection:
    """A connected client. `plane` (the ControlPlane) provides readers / writers (the loop's Poller),
    `buffered` (unsent reply bytes of all clients), `backlog` (fd -> connection with lines left to handle),
    `turn_ends_at()` (when requests must wait for the next turn), `followers` (LogFollowers),
    `on_request(connection, line)`, `drop_unread(connection, size)` and `forget(connection)`."""

    def __init__(self, plane, connection: socket.socket, pid: int):
        self.plane = plane
        self.connection = connection
        self.fd = connection.fileno()
        self.pid = pid
        self.received = bytearray()  # request bytes not handled yet
        self.output = bytearray()  # reply bytes not sent yet
        self.following = None  # the NodeLog while `logs` with follow runs
        self.waiting = 0  # replies still to come (stops and restarts in progress)
        self.reading = True  # False once the client sent end-of-file or a line was refused for good
        self.closed = False
        connection.setblocking(False)
        plane.readers[self.fd] = self.on_readable

    # Requests in

    def on_readable(self) -> None:
        try:
            data = self.connection.recv(CONTROL_RECEIVE_BYTES)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            data = b""
        if not data:
            self.stop_reading()
            return
        self.received += data
        self.handle_lines()

    def handle_lines(self, at_least_one: bool = False) -> None:
        """Handle complete lines: up to CONTROL_REQUESTS_PER_TURN, and none once the plane's time for this
        turn is used up (but one when `at_least_one`). Lines left wait in the plane's backlog for the next
        turn of the loop, and nothing more is read from this client until they are handled."""
        for count in range(CONTROL_REQUESTS_PER_TURN):
            end = self.received.find(b"\n", 0, CONTROL_REQUEST_LIMIT + 1)
            if end < 0 or self.closed or not self.reading:
                break
            if time.monotonic() >= self.plane.turn_ends_at() and not (at_least_one and count == 0):
                break
            line = bytes(self.received[:end])
            del self.received[: end + 1]
            self.plane.on_request(self, line)
        if self.closed or not self.reading:
            return
        if self.received.find(b"\n", 0, CONTROL_REQUEST_LIMIT + 1) >= 0:
            self.plane.readers.pop(self.fd, None)
            self.plane.backlog[self.fd] = self
        elif len(self.received) > CONTROL_REQUEST_LIMIT:
            self.send(refusal("bad_request", f"request line longer than {CONTROL_REQUEST_LIMIT} bytes"))
            self.stop_reading()
        elif self.fd not in self.plane.readers:
            self.plane.readers[self.fd] = self.on_readable

    def stop_reading(self) -> None:
        """No more requests from this client: it closes once what it waits for has been sent."""
        self.reading = False
        self.stop_following()
        self.plane.readers.pop(self.fd, None)
        self.close_when_done()

    # Replies out

    def send(self, reply: dict) -> None:
        import json

        if not self.closed:
            self.send_line(json.dumps(reply).encode() + b"\n")

    def send_line(self, data: bytes) -> None:
        """Send one reply line, already encoded."""
        if self.closed:
            return
        if len(self.output) + len(data) > CONTROL_OUTPUT_LIMIT_BYTES or (
            self.plane.buffered + len(data) > CONTROL_OUTPUT_TOTAL_BYTES
        ):
            self.plane.drop_unread(self, len(self.output) + len(data))
            return
        self.output += data
        self.plane.buffered += len(data)
        if self.fd not in self.plane.writers:
            self.flush()

    def answer(self, reply: dict) -> None:
        """Send the reply to a request answered later (a stop or a restart)."""
        self.waiting -= 1
        self.send(reply)
        self.close_when_done()

    def flush(self) -> None:
        """Send what the socket takes now; wait for it to be writable for the rest."""
        try:
            sent = self.connection.send(self.output, socket.MSG_NOSIGNAL)
        except (BlockingIOError, InterruptedError):
            sent = 0
        except OSError:
            self.close()
            return
        del self.output[:sent]
        self.plane.buffered -= sent
        if self.output:
            if self.fd not in self.plane.writers:
                self.plane.writers[self.fd] = self.flush
            return
        self.plane.writers.pop(self.fd, None)
        self.close_when_done()

    def close_when_done(self) -> None:
        if not self.reading and not self.output and not self.waiting:
            self.close()

    # Following a node's log

    def follow(self, node_log) -> None:
        self.following = node_log
        self.plane.followers.add(node_log, self)

    def stop_following(self) -> None:
        if self.following is not None:
            self.plane.followers.remove(self.following, self)
            self.following = None

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.stop_following()
        self.plane.readers.pop(self.fd, None)
        self.plane.writers.pop(self.fd, None)
        self.plane.backlog.pop(self.fd, None)
        self.plane.buffered -= len(self.output)
        self.output.clear()
        close_quietly(self.connection)
        self.plane.forget(self)


class LogFollowers:
    """The connections following each node's log (`logs` with follow): one listener a NodeLog, and each new
    line encoded once for all of them."""

    def __init__(self):
        self.connections = {}  # NodeLog -> {fd: ControlConnection}

    def add(self, node_log, connection: ControlConnection) -> None:
        if node_log not in self.connections:
            self.connections[node_log] = {}
            node_log.listeners.append(lambda line, node_log=node_log: self.on_line(node_log, line))
        self.connections[node_log][connection.fd] = connection

    def remove(self, node_log, connection: ControlConnection) -> None:
        self.connections.get(node_log, {}).pop(connection.fd, None)

    def on_line(self, node_log, line: str) -> None:
        import json

        following = self.connections[node_log]
        if following:
            data = json.dumps({"line": line}).encode() + b"\n"
            for connection in list(following.values()):
                connection.send_line(data)


def close_quietly(connection: socket.socket) -> None:
    """Close a client's socket after discarding what it sent and was not read (up to CONTROL_RECEIVE_BYTES),
    so that it sees the end of its replies, not a reset connection."""
    try:
        connection.setblocking(False)
        connection.recv(CONTROL_RECEIVE_BYTES)
    except OSError:
        pass
    connection.close()
