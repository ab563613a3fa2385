"""Chunked inference: the model runs in a background thread on the newest observation while the node goes on.

An INFERENCE node whose topic is trajectory_msgs/msg/JointTrajectory hands the newest observation to
this worker whenever it is idle (at most once per 1/rate_hz); the worker runs the policy's whole
action chunk on it and publishes it at once as one JointTrajectory: header stamped with the
observation's time, point i at time_from_start i/rate_hz (rate_hz is the rate the policy's actions were
recorded at). The actuator executes the chunk at its own control rate while the next call runs, so a
model call may last several control periods without a gap in the commands.

Each call's latency is measured; a summary is logged every LATENCY_LOG_PERIOD_S. When a chunk has run
out before the next one was published, the worker says so once, with the numbers.
"""

import threading
import time

import numpy as np

LATENCY_LOG_PERIOD_S = 30.0
IDLE_WAIT_S = 0.1  # how long the worker sleeps between looks at its stop flag when no observation waits


def percentile(samples: list[float], fraction: float) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, int(round(fraction * (len(ordered) - 1))))]


class ChunkedInference:
    """The background inference thread of one node; `publish(chunk, stamp_s)` sends a chunk."""

    def __init__(self, runner, publish, step_s: float, log, clock):
        self.runner, self.publish, self.step_s, self.log, self.clock = runner, publish, step_s, log, clock
        self.error: BaseException | None = None
        self.calls = 0
        self.latencies_s: list[float] = []  # since the last summary
        self.last_latency_s = 0.0
        self.chunk_end_s: float | None = None  # when the last published chunk runs out (ROS clock)
        self.warned_run_out = False
        self._reset = False
        self._pending: tuple[dict, float, str] | None = None
        self._busy = False
        self._wake = threading.Condition()
        self._stopped = False
        self._next_summary = time.monotonic() + LATENCY_LOG_PERIOD_S
        self.thread = threading.Thread(target=self._run, name="chunked-inference", daemon=True)

    def start(self) -> None:
        self.thread.start()

    def stop(self) -> None:
        with self._wake:
            self._stopped = True
            self._wake.notify()

    def idle(self) -> bool:
        """Whether the worker would take an observation now (no call running, none waiting)."""
        with self._wake:
            return not self._busy and self._pending is None

    def offer(self, observation: dict, stamp_s: float, task: str = "") -> None:
        """The observation for the next call (taken at `stamp_s`, ROS clock), with the policy's instruction."""
        with self._wake:
            self._pending = (observation, stamp_s, task)
            self._wake.notify()

    def interrupt(self) -> None:
        """The inputs stopped: drop a waiting observation and reset the policy before the next call."""
        with self._wake:
            self._pending = None
            self._reset = True

    def _run(self) -> None:
        try:
            while True:
                with self._wake:
                    while self._pending is None and not self._stopped:
                        self._wake.wait(IDLE_WAIT_S)
                    if self._stopped:
                        return
                    (observation, stamp_s, task), self._pending = self._pending, None
                    self._busy, reset, self._reset = True, self._reset, False
                if reset:
                    self.runner.reset()
                self._call(observation, stamp_s, task)
                with self._wake:
                    self._busy = False
        except BaseException as exc:  # reported by the node's loop, which ends the process with it
            self.error = exc

    def _call(self, observation: dict, stamp_s: float, task: str) -> None:
        started = time.perf_counter()
        chunk = self.runner.act_chunk(observation, task)
        latency = time.perf_counter() - started
        self.calls += 1
        self.last_latency_s = latency
        self.latencies_s.append(latency)
        if not np.all(np.isfinite(chunk)):
            self.log.warning("no action: the policy returned a non-finite action chunk", throttle_duration_sec=2.0)
            return
        now = self.clock()
        self._check_run_out(now, len(chunk))
        self.publish(chunk, stamp_s)
        self.chunk_end_s = stamp_s + (len(chunk) - 1) * self.step_s
        self._summarise(len(chunk))

    def _check_run_out(self, now_s: float, steps: int) -> None:
        if self.warned_run_out or self.chunk_end_s is None or now_s <= self.chunk_end_s:
            return
        self.warned_run_out = True
        self.log.warning(
            f"the model cannot keep up: a chunk of {steps} actions lasts {1000 * (steps - 1) * self.step_s:.0f} ms "
            f"at {1 / self.step_s:g} Hz, a model call takes {1000 * percentile(self.latencies_s, 0.5):.0f} ms "
            f"(p50 of {len(self.latencies_s)}, last {1000 * self.last_latency_s:.0f} ms), and the last chunk ran out "
            f"{1000 * (now_s - self.chunk_end_s):.0f} ms before this one: the actuator held its last goal meanwhile "
            "(said once)"
        )

    def _summarise(self, steps: int) -> None:
        if time.monotonic() < self._next_summary or not self.latencies_s:
            return
        self._next_summary = time.monotonic() + LATENCY_LOG_PERIOD_S
        samples, self.latencies_s = self.latencies_s, []
        self.log.info(
            f"model calls: {len(samples)} in the last {LATENCY_LOG_PERIOD_S:g} s, latency p50 "
            f"{1000 * percentile(samples, 0.5):.0f} ms p99 {1000 * percentile(samples, 0.99):.0f} ms "
            f"max {1000 * max(samples):.0f} ms; chunks of {steps} actions ({1000 * steps * self.step_s:.0f} ms)"
        )
