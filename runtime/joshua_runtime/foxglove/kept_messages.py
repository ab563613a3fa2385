"""The newest messages of a transient-local topic, kept for Foxglove clients that subscribe later."""

import threading
from collections import deque


class KeptMessages:
    """What a transient-local ROS subscription would get on joining: the newest `depth` messages
    (serialized, with their log times). Filled by the ROS executor, read by the server's thread."""

    def __init__(self, depth: int):
        self._messages: deque[tuple[bytes, int]] = deque(maxlen=max(depth, 1))
        self._lock = threading.Lock()

    def keep(self, data: bytes, log_time: int) -> None:
        with self._lock:
            self._messages.append((data, log_time))

    def snapshot(self) -> list[tuple[bytes, int]]:
        """The kept messages, oldest first."""
        with self._lock:
            return list(self._messages)
