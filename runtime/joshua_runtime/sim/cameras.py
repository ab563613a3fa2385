"""Offscreen camera rendering in one thread, each camera at its own wall-clock rate.

The OpenGL context of a mujoco.Renderer belongs to the thread that made it, so one thread creates
every renderer, renders, and frees them. For each frame it copies the scene under the engine's
lock (mjv_updateScene, fast) and renders outside it, so physics keeps stepping while a frame is
drawn. A camera that cannot keep its rate skips frames instead of queueing them.
"""

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from joshua_runtime.sim.engine import SimulationEngine
from joshua_runtime.sim.gl_backend import render_failure

# Time allowed for the render thread to create its contexts at start.
RENDERER_START_TIMEOUT_S = 20.0
# Time allowed for the render thread to finish its frame and free its contexts on stop().
STOP_JOIN_TIMEOUT_S = 0.3
# Longest the render thread sleeps before it checks for a stop request.
MAX_SLEEP_S = 0.05

FrameCallback = Callable[[np.ndarray, float], None]


@dataclass
class CameraStream:
    """One simulated camera: which model camera, image size, rate, and who receives the frames.

    `on_frame(pixels, sim_time)` gets an (height, width, 3) uint8 RGB array that is reused for the
    next frame of this stream, so it must be consumed (copied or serialised) before returning.
    """

    camera: int
    width: int
    height: int
    rate_hz: float
    on_frame: FrameCallback
    frames: int = 0
    skipped: int = 0
    _due: float = field(default=0.0, repr=False)


class CameraThread:
    """Renders every CameraStream of an engine at its rate until stop()."""

    def __init__(self, engine: SimulationEngine, streams: list[CameraStream], gl_backend: str = ""):
        self.engine = engine
        self.streams = streams
        self.gl_backend = gl_backend
        self._stop = threading.Event()
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        """Create the renderers in the render thread; raise DeviceError when that fails."""
        if not self.streams:
            return
        self._grow_offscreen_buffer()
        self._thread = threading.Thread(target=self._run, name="sim-cameras", daemon=True)
        self._thread.start()
        self._ready.wait(RENDERER_START_TIMEOUT_S)
        if self._error is not None:
            self._thread.join(STOP_JOIN_TIMEOUT_S)
            self._thread = None
            raise render_failure(self.gl_backend or "egl", self._error)

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(STOP_JOIN_TIMEOUT_S)
            self._thread = None

    def _grow_offscreen_buffer(self) -> None:
        """Make the model's offscreen framebuffer large enough for the largest stream."""
        visual = self.engine.model.vis.global_
        visual.offwidth = max(visual.offwidth, max(s.width for s in self.streams))
        visual.offheight = max(visual.offheight, max(s.height for s in self.streams))

    def _run(self) -> None:
        renderers: dict[tuple[int, int], mujoco.Renderer] = {}
        try:
            for stream in self.streams:
                size = (stream.height, stream.width)
                if size not in renderers:
                    renderers[size] = mujoco.Renderer(self.engine.model, *size)
        except Exception as exc:  # any GL failure is reported by start() as one DeviceError
            self._error = exc
            self._ready.set()
            self._close(renderers)
            return
        self._ready.set()
        buffers = {id(s): np.empty((s.height, s.width, 3), dtype=np.uint8) for s in self.streams}
        now = time.monotonic()
        for stream in self.streams:
            stream._due = now
        try:
            while not self._stop.is_set():
                stream = min(self.streams, key=lambda s: s._due)
                wait = stream._due - time.monotonic()
                if wait > 0:
                    self._stop.wait(min(wait, MAX_SLEEP_S))
                    continue
                renderer = renderers[(stream.height, stream.width)]
                with self.engine.lock:
                    renderer.update_scene(self.engine.data, camera=stream.camera)
                    sim_time = self.engine.data.time
                pixels = renderer.render(out=buffers[id(stream)])
                stream.on_frame(pixels, sim_time)
                stream.frames += 1
                self._schedule_next(stream)
        finally:
            self._close(renderers)

    @staticmethod
    def _schedule_next(stream: CameraStream) -> None:
        period = 1.0 / stream.rate_hz
        stream._due += period
        now = time.monotonic()
        if stream._due < now:
            missed = int((now - stream._due) / period) + 1
            stream.skipped += missed
            stream._due += missed * period

    @staticmethod
    def _close(renderers: dict) -> None:
        for renderer in renderers.values():
            renderer.close()
