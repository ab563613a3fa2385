"""A network camera for the tests: an MJPEG stream over HTTP (multipart/x-mixed-replace) on 127.0.0.1.

Each connection gets `frames` JPEG frames `period_s` apart, then, as told, the stream stalls (the
connection stays open and nothing more comes, as from a hung camera) or ends (the connection closes).
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
    def __init__(self, frames: int, then: str = "stall", size: tuple[int, int] = (160, 120), period_s: float = 0.05):
        assert then in ("stall", "end")
        width, height = size
        self.jpeg = cv2.imencode(".jpg", np.full((height, width, 3), 128, np.uint8))[1].tobytes()
        self.frames, self.then, self.period_s = frames, then, period_s
        self.last_frame_at = 0.0  # time.monotonic() when the newest frame was sent
        self.stopping = threading.Event()
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.listener.settimeout(ACCEPT_POLL_S)
        self.url = f"http://127.0.0.1:{self.listener.getsockname()[1]}/stream.mjpg"
        self.threads = [threading.Thread(target=self._accept, daemon=True)]

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
                for _ in range(self.frames):
                    part = b"--%s\r\nContent-Type: image/jpeg\r\nContent-Length: %d\r\n\r\n" % (
                        BOUNDARY,
                        len(self.jpeg),
                    )
                    connection.sendall(part + self.jpeg + b"\r\n")
                    self.last_frame_at = time.monotonic()
                    if self.stopping.wait(self.period_s):
                        return
            except OSError:  # the client went away
                return
            if self.then == "stall":
                self.stopping.wait()
