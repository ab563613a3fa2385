"""OpenCV camera driver: a V4L2 device index or a video file/URL, frames as bgr8 PerceptionPackets.

A video file is played in a loop (it rewinds at its end), so a recorded clip can stand in for a
camera. Frames whose size differs from the requested width x height are resized to it. A stream
(a URL) is opened through FFmpeg with STREAM_OPEN_TIMEOUT_S and STREAM_READ_TIMEOUT_S in place of
FFmpeg's 30 s, so that a stalled stream does not hold a read that long.
"""

import os
import time

import cv2

from joshua_core.schema import PerceptionPacket
from joshua_runtime.drivers.driver import Driver
from joshua_runtime.errors import DeviceError

ENCODING = "bgr8"
BYTES_PER_PIXEL = 3
OPENCV_LOG_SILENT = 0  # cv2.setLogLevel level that prints nothing
FFMPEG_LOG_QUIET = "-8"  # AV_LOG_QUIET, for OPENCV_FFMPEG_LOGLEVEL
STREAM_OPEN_TIMEOUT_S = 5.0
STREAM_READ_TIMEOUT_S = 10.0


def _silence_opencv() -> None:
    """OpenCV and FFmpeg log their own warnings to stderr; the driver reports failures as one DeviceError line."""
    cv2.setLogLevel(OPENCV_LOG_SILENT)
    os.environ["OPENCV_FFMPEG_LOGLEVEL"] = FFMPEG_LOG_QUIET


class CameraDriver(Driver):
    """Reads frames from `video_source` when it is set, else from `/dev/video<camera_index>`."""

    def __init__(
        self,
        camera_index: int = 0,
        video_source: str = "",
        width: int = 640,
        height: int = 480,
        fps: float = 30.0,
        frame_id: str = "camera",
        loop: bool = True,
    ):
        self.camera_index = camera_index
        self.video_source = video_source
        self.width = width
        self.height = height
        self.fps = fps
        self.frame_id = frame_id
        self.loop = loop
        self.frames_read = 0
        self._capture = None

    @property
    def description(self) -> str:
        if self.video_source:
            return f"video source {self.video_source}"
        return f"camera {self.camera_index} (/dev/video{self.camera_index})"

    @property
    def is_file(self) -> bool:
        return bool(self.video_source) and "://" not in self.video_source

    def open(self) -> None:
        _silence_opencv()
        if self.is_file and not os.path.isfile(self.video_source):
            raise DeviceError(f"cannot open {self.description}: no such file")
        if not self.video_source:
            if self.camera_index < 0:
                raise DeviceError(f"cannot open a camera: no video_source and invalid index {self.camera_index}")
            if not os.path.exists(f"/dev/video{self.camera_index}"):
                raise DeviceError(f"cannot open {self.description}: no such device")
        if self.is_file:
            capture = cv2.VideoCapture(self.video_source)
        elif self.video_source:
            timeouts = [
                cv2.CAP_PROP_OPEN_TIMEOUT_MSEC,
                int(STREAM_OPEN_TIMEOUT_S * 1000),
                cv2.CAP_PROP_READ_TIMEOUT_MSEC,
                int(STREAM_READ_TIMEOUT_S * 1000),
            ]
            capture = cv2.VideoCapture(self.video_source, cv2.CAP_FFMPEG, timeouts)
        else:
            capture = cv2.VideoCapture(self.camera_index, cv2.CAP_V4L2)
        if not capture.isOpened():
            capture.release()
            raise DeviceError(f"cannot open {self.description}: OpenCV could not open it")
        if not self.video_source:
            capture.set(cv2.CAP_PROP_FRAME_WIDTH, self.width)
            capture.set(cv2.CAP_PROP_FRAME_HEIGHT, self.height)
            capture.set(cv2.CAP_PROP_FPS, self.fps)
        self._capture = capture

    def close(self) -> None:
        capture, self._capture = self._capture, None
        if capture is not None:
            capture.release()

    def read_frame(self):
        """The next frame as a HxWx3 uint8 BGR array of the requested size."""
        if self._capture is None:
            raise DeviceError(f"{self.description} is not open")
        ok, frame = self._capture.read()
        if not ok and self.is_file and self.loop:
            self._capture.set(cv2.CAP_PROP_POS_FRAMES, 0)
            ok, frame = self._capture.read()
        if not ok or frame is None:
            raise DeviceError(f"{self.description} stopped delivering frames")
        if frame.ndim == 2:
            frame = cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
        if frame.shape[1] != self.width or frame.shape[0] != self.height:
            frame = cv2.resize(frame, (self.width, self.height), interpolation=cv2.INTER_AREA)
        self.frames_read += 1
        return frame

    def read(self) -> PerceptionPacket:
        """The next frame as a PerceptionPacket with a bgr8 image, stamped when it was read."""
        frame = self.read_frame()
        return frame_to_packet(frame, self.frame_id, time.time_ns())


def frame_to_packet(frame, frame_id: str, stamp_ns: int) -> PerceptionPacket:
    """Wrap a HxWx3 uint8 BGR array in a PerceptionPacket."""
    height, width = frame.shape[:2]
    packet = PerceptionPacket(frame_id=frame_id)
    packet.timestamp.FromNanoseconds(stamp_ns)
    image = packet.image
    image.width = width
    image.height = height
    image.encoding = ENCODING
    image.step = width * BYTES_PER_PIXEL
    image.data = frame.tobytes()
    return packet
