"""CAMERA_PUBLISHER: frames of an OpenCV camera (device index or video_source) as Image or CompressedImage
(and a JPEG copy for other hosts, camera_output.py).

A reader thread reads one frame every 1/rate_hz at width x height and publishes it on `topic`,
stamped when it was read, with the node's frame_id; the executor stays free to notice a stop signal.
A camera that cannot be opened or stops delivering frames ends the node with exit code 3: a read
that fails (a device unplugged, a stream that ended) at once, one that hangs (a stalled stream, a
frozen device) once it has waited DEVICE_SILENCE_S (FIRST_FRAME_TIMEOUT_S for the first frame, while
a camera starts up). A watchdog timer on the executor raises either.
"""

import threading
import time

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_runtime.drivers.camera import CameraDriver
from joshua_runtime.errors import DeviceError, JoshuaError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.camera_output import CameraOutput

# A camera may take this long to deliver its first frame after it was opened (exposure, USB start-up).
FIRST_FRAME_TIMEOUT_S = 5.0
WATCHDOG_PERIOD_S = 0.05
READER_JOIN_TIMEOUT_S = 0.3


class CameraPublisher(JoshuaNode):
    camera = None
    reader = None

    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        self.period = settings_checks.period_s(self.settings)
        width, height = settings_checks.image_size(self.settings)
        self.output = CameraOutput(self, topic, self.settings.compressed_topic)
        self.camera = CameraDriver(
            camera_index=self.settings.camera_index,
            video_source=self.settings.video_source,
            width=width,
            height=height,
            fps=self.settings.rate_hz,
            frame_id=self.settings.frame_id,
        )
        self.camera.open()
        self.stopping = threading.Event()
        self.failure: JoshuaError | None = None
        self.reading_since: float | None = None  # time.monotonic() when the read in progress began
        self.reader = threading.Thread(target=self._read_frames, name="camera-reader", daemon=True)
        self.reader.start()
        self.ros.create_timer(WATCHDOG_PERIOD_S, self._watch)

    def _read_frames(self) -> None:
        next_read = time.monotonic()
        try:
            while not self.stopping.wait(max(0.0, next_read - time.monotonic())):
                next_read += self.period
                self.reading_since = time.monotonic()
                packet = self.camera.read()
                self.reading_since = None
                self.output.publish(packet)
                next_read = max(next_read, time.monotonic() - self.period)  # no burst after a slow read
        except JoshuaError as exc:
            self.failure = exc

    def _watch(self) -> None:
        if self.failure is not None:
            raise self.failure
        since = self.reading_since
        limit = DEVICE_SILENCE_S if self.camera.frames_read else FIRST_FRAME_TIMEOUT_S
        if since is not None and time.monotonic() - since > limit:
            raise DeviceError(f"{self.camera.description} stopped delivering frames: no frame for {limit:g} s")

    def close(self) -> None:
        if self.reader is not None:
            self.stopping.set()
            self.reader.join(READER_JOIN_TIMEOUT_S)
            if self.reader.is_alive():
                return  # a read still hangs in OpenCV: releasing the capture under it could crash; exit frees it
        if self.camera is not None:
            self.camera.close()
