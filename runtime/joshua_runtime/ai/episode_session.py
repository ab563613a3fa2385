"""The recorder's episodes as lerobot-record runs them: recording, a reset period, the next episode.

A session is in one phase at a time: `recording` an episode, `resetting` (a reset period of
reset_time_s between episodes, nothing recorded) or `idle`. Commands (episode_protocol.py) move it
between phases and hand the episode work to the writer (WriterProcess or EpisodeWriter); `tick()`,
called at every frame period, ends an episode that has lasted episode_time_s and a reset period that
is over. The session answers the commands it can answer itself through `answer(event, **details)`;
the writer answers those that need the disk (saved, discarded, removed).
"""

import time

from joshua_runtime.ai import episode_protocol as protocol

RECORDING, RESETTING, IDLE = protocol.PHASES


class EpisodeSession:
    """Phase, task, timers and counts of a recorder's episodes."""

    def __init__(
        self,
        writer,
        answer,
        log,
        default_task: str,
        episode_time_s: float = 0.0,
        reset_time_s: float = 0.0,
        episodes: int = 0,
        clock=time.monotonic,
    ):
        self.writer = writer
        self.answer = answer
        self.log = log
        self.default_task = default_task
        self.task = default_task
        self.episode_time_s = episode_time_s
        self.reset_time_s = reset_time_s
        self.episodes = episodes  # saved in the dataset, also the index of the episode in progress
        self.clock = clock
        self.phase = IDLE
        self.since = clock()
        self.frames = self.skipped = 0
        self.first_frame_s: float | None = None
        self.undoable = False  # an episode saved since the start that `rerecord` may remove

    @property
    def recording(self) -> bool:
        return self.phase == RECORDING

    def begin(self, task: str = "") -> None:
        """Start recording an episode (with this task, else the last one)."""
        self.task = task or self.task
        self.writer.start_episode(self.task)
        self._enter(RECORDING)
        self.frames = self.skipped = 0
        self.first_frame_s = None
        self.log.info(f"episode started (task: {self.task})")

    def command(self, text: str) -> None:
        word, _, argument = text.strip().partition(" ")
        handler = getattr(self, f"_{word}", None) if word in protocol.COMMANDS else None
        if handler is None:
            self._ignore(f"unknown episode command {text!r} (use {', '.join(protocol.COMMANDS)}; start takes a task)")
        else:
            handler(argument.strip())

    def tick(self) -> None:
        """End an episode that has lasted episode_time_s, and a reset period that is over."""
        elapsed = self.clock() - self.since
        if self.recording and self.episode_time_s > 0 and elapsed >= self.episode_time_s:
            self.log.info(f"episode_time_s ({self.episode_time_s:g} s) reached")
            self._end(save=True)
            self._after_episode()
        elif self.phase == RESETTING and elapsed >= self.reset_time_s:
            self.log.info("reset period over")
            self.begin()

    def frame_recorded(self) -> None:
        self.frames += 1
        if self.frames == 1:
            self.first_frame_s = self.clock()
            self.log.info("first frame of the episode recorded")

    def frame_skipped(self) -> None:
        self.skipped += 1

    def close(self) -> None:
        """Save the episode in progress (SIGINT, SIGTERM)."""
        if self.recording:
            self._end(save=True)

    def progress(self, writer_ready: bool, last_event: int) -> dict:
        """The progress report (episode_protocol.py); `last_event`: the seq of the recorder's last event."""
        elapsed = self.clock() - self.since
        limit = {RECORDING: self.episode_time_s, RESETTING: self.reset_time_s}.get(self.phase, 0.0)
        return {
            "phase": self.phase,
            "task": self.task,
            "episodes": self.episodes,
            "elapsed_s": round(elapsed, 3),
            "remaining_s": round(max(0.0, limit - elapsed), 3) if limit > 0 else None,
            "frames": self.frames if self.recording else 0,
            "skipped": self.skipped if self.recording else 0,
            "writer": "ready" if writer_ready else "loading",
            "seq": last_event,
        }

    # The commands.
    def _start(self, task: str) -> None:
        if self.recording:
            self._ignore("episode command 'start' ignored: an episode is already recording")
            return
        self.begin(task or self.default_task)
        self.answer("started", message=f"episode started (task: {self.task})")

    def _stop(self, _argument: str) -> None:
        if self.recording:
            self._end(save=True)  # the writer answers once the episode is saved
        elif self.phase == RESETTING:
            self._enter(IDLE)
            self.log.info("reset period ended; no episode recording")
            self.answer("stopped", message="reset period ended; no episode recording")
        else:
            self._ignore("episode command 'stop' ignored: no episode is recording")

    def _discard(self, _argument: str) -> None:
        if not self.recording:
            self._ignore("episode command 'discard' ignored: no episode is recording")
            return
        self._end(save=False)

    def _next(self, _argument: str) -> None:
        if self.recording:
            self._end(save=True)
            self._after_episode()
        else:
            self.begin()
            self.answer("started", message=f"episode started (task: {self.task})")

    def _rerecord(self, _argument: str) -> None:
        if self.recording:
            frames = self.frames
            self._end(save=False)
            then = f"resetting for {self.reset_time_s:g} s, then recording it again" if self.reset_time_s > 0 else ""
            self.answer(
                "rerecording",
                message=f"dropped the episode in progress ({frames} frames); {then or 'recording it again'}",
            )
            self._after_episode()
        elif self.undoable:
            self.undoable = False
            self.writer.undo_last_episode()  # the writer answers "removed"
            self.episodes -= 1
            self.begin()
        else:
            self._ignore("nothing to re-record: no episode in progress, and none saved since the recorder started")

    # Phases.
    def _enter(self, phase: str) -> None:
        self.phase = phase
        self.since = self.clock()

    def _end(self, save: bool) -> None:
        if save:
            self.writer.end_episode()
            if self.frames:
                self.undoable = True
                self.episodes += 1  # until the writer says how many the dataset holds
        else:
            self.writer.discard_episode()
        span = self.clock() - self.first_frame_s if self.first_frame_s is not None else 0.0
        self.log.info(
            f"episode {'stopped' if save else 'discarded'} after {self.frames} frames "
            f"({self.skipped} skipped) over {span:.3f} s"
        )
        self._enter(IDLE)

    def _after_episode(self) -> None:
        if self.reset_time_s > 0:
            self._enter(RESETTING)
            self.log.info(f"resetting for {self.reset_time_s:g} s")
        else:
            self.begin()

    def _ignore(self, reason: str) -> None:
        self.log.warning(reason)
        self.answer("ignored", message=reason)
