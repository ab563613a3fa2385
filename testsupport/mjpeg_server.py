"""A network camera for tests and benchmarks: an MJPEG stream over HTTP (multipart/x-mixed-replace) on 127.0.0.1.

Each connection gets a JPEG frame every `period_s` until the caller says `stall()` (the connection
stays open and nothing more comes, as from a hung camera) or `end()` (the connection closes).
"""

import socket
import threading
import time

import cv2
import numpy as np

BOUNDARY = b"frame"
JOIN_TIMEOUT_S = 2.0
ACCEPT_POLL_S = 0.1


class MjpegServer:
    def __init__(self, size: tuple[int, int] = (160, 120), period_s: float = 0.2):
        width, height = size
        self.jpeg = cv2.imencode(".jpg", np.full((height, width, 3), 128, np.uint8))[1].tobytes()
        self.period_s = period_s
        self.streaming = threading.Event()
        self.streaming.set()
        self.closing = False  # after the stream stops: close the connections (True) or keep them open
        self.stopped_at = 0.0  # time.monotonic() when stall() or end() was called
        self.stopping = threading.Event()
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.listener.settimeout(ACCEPT_POLL_S)
        self.url = f"http://127.0.0.1:{self.listener.getsockname()[1]}/stream.mjpg"
        self.threads = [threading.Thread(target=self._accept, daemon=True)]

    def stall(self) -> None:
        """From now on, send nothing and keep every connection open."""
        self.stopped_at = time.monotonic()
        self.streaming.clear()

    def end(self) -> None:
        """From now on, close every connection after its current frame."""
        self.closing = True
        self.stall()

    def __enter__(self) -> "MjpegServer":
        self.threads[0].start()
        return self

    def __exit__(self, *exc_info) -> None:
        self.stopping.set()
        for thread in self.threads:
            thread.join(JOIN_TIMEOUT_S)
        self.listener.close()

    def _accept(self) -> None:
        while not self.stopping.is_set():
            try:
                connection, _ = self.listener.accept()
            except TimeoutError:
                continue
            thread = threading.Thread(target=self._serve, args=(connection,), daemon=True)
            self.threads.append(thread)
            thread.start()

    def _serve(self, connection: socket.socket) -> None:
        with connection:
            try:
                connection.recv(65536)  # the request; whatever it asks, it gets the stream
                connection.sendall(
                    b"HTTP/1.0 200 OK\r\nContent-Type: multipart/x-mixed-replace; boundary=" + BOUNDARY + b"\r\n\r\n"
                )
                while self.streaming.is_set():
                    part = b"--%s\r\nContent-Type: image/jpeg\r\nContent-Length: %d\r\n\r\n" % (
                        BOUNDARY,
                        len(self.jpeg),
                    )
                    connection.sendall(part + self.jpeg + b"\r\n")
                    if self.stopping.wait(self.period_s):
                        return
            except OSError:  # the client went away
                return
            if not self.closing:
                self.stopping.wait()
