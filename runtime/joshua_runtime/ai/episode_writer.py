"""The recorder's writing thread: feeds frames to a LeRobotDataset and commits each finished episode.

Every episode is written into a staging copy of the dataset (see `staged_directory.py`), saved,
finalised (LeRobot's parquet writers only write their footer on close), then swapped in atomically.
So the dataset at `output_directory` is always a finalised dataset that `LeRobotDataset` loads, and
a process killed at any moment loses at most the episode in progress. Each episode after the first
goes to new data/video/metadata files, as LeRobot does when it resumes recording a dataset. An episode
with frames that cannot be saved (full disk, directory not writable) is a DataLostError: the node
exits 6 and says which episode did not reach which directory. That happens at the first write that
fails, not when the episode is saved: a PNG the image writer could not write (checked_image_writer.py)
or a video file the streaming encoder could not write ends the episode at the next frame.

Video datasets use LeRobot's streaming encoder (frames are encoded while recording, so saving an
episode at SIGINT is quick), kept quiet (ENCODER_LOG_VARIABLE); image datasets write PNG files through
threads of the recorder's own (checked_image_writer.py).
"""

import json
import os
import queue
import shutil
import threading
from pathlib import Path

from joshua_runtime.ai import private_cache, staged_directory
from joshua_runtime.errors import DataLostError, JoshuaError, SettingsError

VIDEO_CODEC = "libsvtav1"
# SVT-AV1 prints a banner and its configuration (~20 lines) to stderr at every episode's encoder start,
# at its default level 3 (info). It reads its level from this variable at each start; the recorder
# keeps it to errors only unless the environment sets it (SVT_LOG=3 for the banner, 4 for debug).
ENCODER_LOG_VARIABLE = "SVT_LOG"
QUIET_ENCODER_LOG_LEVEL = "1"
IMAGE_WRITER_THREADS = 4
CACHE_PREFIX = "joshua-recorder-cache-"  # the Hugging Face datasets cache of a writer, in /tmp
# LeRobot's default features, added by LeRobot itself; ignored when comparing with an existing dataset.
_DEFAULT_FEATURES = ("timestamp", "frame_index", "episode_index", "index", "task_index")


class EpisodeWriter:
    """Owns the dataset on disk; commands are queued and applied in order by one thread."""

    def __init__(self, output_directory: str, fps: int, robot_type: str, use_videos: bool, log, on_event=None):
        """`on_event(event, **details)` is called from the writing thread: "opened" once the dataset
        directory is recovered and ready, then "saved", "empty", "discarded" or "failed" per episode."""
        self.on_event = on_event or (lambda event, **details: None)
        self.target = Path(output_directory).expanduser().absolute()
        self.fps = fps
        self.robot_type = robot_type
        self.use_videos = use_videos
        self.log = log
        self.error: BaseException | None = None
        self.saved_episodes = 0
        self._commands: queue.Queue = queue.Queue()
        self._features: dict | None = None
        self._dataset = None
        self._images = None  # the CheckedImageWriter of an image dataset in progress
        self._task = ""
        self._frames = 0
        self._last_save: tuple[int, int, bool] | None = None  # (episode, frames, had a previous version)
        # Held under a lock, so that the next writer removes it if this process is killed before close().
        self._cache, self._cache_lock = private_cache.make(CACHE_PREFIX)
        os.environ.setdefault(ENCODER_LOG_VARIABLE, QUIET_ENCODER_LOG_LEVEL)
        self._import_lerobot()
        self._thread = threading.Thread(target=self._run, name="episode-writer", daemon=True)
        self._thread.start()

    # Commands, called from the ROS thread.
    def configure(self, features: dict) -> None:
        self._commands.put(("configure", features))

    def start_episode(self, task: str) -> None:
        self._commands.put(("start", task))

    def add_frame(self, frame: dict) -> None:
        self._commands.put(("frame", frame))

    def end_episode(self) -> None:
        self._commands.put(("stop", None))

    def discard_episode(self) -> None:
        self._commands.put(("discard", None))

    def undo_last_episode(self) -> None:
        """Remove the episode this writer saved last from the dataset (to record it again)."""
        self._commands.put(("undo", None))

    def close(self) -> None:
        """Apply every queued command (saving the episode in progress if asked), then stop the thread."""
        self._commands.put(("close", None))
        self._thread.join()
        staged_directory.drop_previous(self.target)
        if self._cache_lock is not None:
            self._restore_datasets_cache()
            private_cache.remove(self._cache, self._cache_lock)
            self._cache_lock = None

    def _import_lerobot(self) -> None:
        """Import LeRobot now: an import in the writing thread would starve the ROS thread for seconds."""
        # Keep the Hugging Face datasets cache of this process private (LeRobot reloads the dataset
        # when it resumes it), and delete it at close.
        import datasets.config

        self._previous_cache_variable = os.environ.get("HF_DATASETS_CACHE")
        self._previous_cache = datasets.config.HF_DATASETS_CACHE
        os.environ["HF_DATASETS_CACHE"] = self._cache
        datasets.config.HF_DATASETS_CACHE = Path(self._cache)
        import lerobot.datasets.lerobot_dataset  # noqa: F401

    def _restore_datasets_cache(self) -> None:
        """Point the datasets library back where it was: a dataset this process reads after close() would
        otherwise make the removed cache again, and nobody would remove it."""
        import datasets.config

        if os.environ.get("HF_DATASETS_CACHE") == self._cache:
            if self._previous_cache_variable is None:
                del os.environ["HF_DATASETS_CACHE"]
            else:
                os.environ["HF_DATASETS_CACHE"] = self._previous_cache_variable
        if datasets.config.HF_DATASETS_CACHE == Path(self._cache):
            datasets.config.HF_DATASETS_CACHE = self._previous_cache

    # The writing thread.
    def _run(self) -> None:
        try:
            staged_directory.recover(self.target)
            self.on_event("opened")
            while True:
                command, argument = self._commands.get()
                if command == "close":
                    return
                getattr(self, f"_{command}")(argument)
        except BaseException as exc:  # reported by the node through `error`
            if self._frames and not isinstance(exc, SettingsError):
                exc = DataLostError(
                    f"episode of {self._frames} frames lost, not saved to {self.target}: {type(exc).__name__}: {exc}"
                )
            elif not isinstance(exc, JoshuaError):
                exc = JoshuaError(f"recording failed: {type(exc).__name__}: {exc}")
            self.error = exc
            self.on_event("failed", message=str(exc))
        finally:
            if self.error is not None:
                self._drop_dataset()

    def _configure(self, features: dict) -> None:
        self._features = features

    def _start(self, task: str) -> None:
        self._task = task
        self._frames = 0

    def _frame(self, frame: dict) -> None:
        if self._dataset is None:
            self._dataset = self._open()
        frame["task"] = self._task
        self._dataset.add_frame(frame)
        self._frames += 1
        if self._images is not None:
            self._images.check()  # a PNG that could not be written ends the episode now

    def _stop(self, _argument) -> None:
        if self._dataset is None or self._frames == 0:
            self.log.info("episode ended without frames; nothing saved")
            self._drop_dataset()
            self.on_event("empty", frames=0, message="episode ended without frames; nothing saved")
            return
        dataset, frames = self._dataset, self._frames
        episode = dataset.meta.total_episodes
        dataset.save_episode()
        dataset.stop_image_writer()
        dataset.finalize()
        self._dataset = self._images = None
        self._last_save = (episode, frames, staged_directory.commit(self.target))
        self._clear_cache()
        self.saved_episodes += 1
        self.log.info(f"episode {episode} saved: {frames} frames, {episode + 1} episodes in {self.target}")
        self.on_event(
            "saved",
            episode=episode,
            frames=frames,
            episodes=episode + 1,
            message=f"saved episode {episode} ({frames} frames) in {self.target}",
        )

    def _discard(self, _argument) -> None:
        frames = self._frames
        self.log.info(f"episode discarded ({frames} frames)")
        self._drop_dataset()
        self.on_event("discarded", frames=frames, message=f"discarded the episode ({frames} frames)")

    def _undo(self, _argument) -> None:
        if self._last_save is None or self._dataset is not None:
            reason = "an episode is being written" if self._last_save else "no episode saved since the recorder started"
            self.on_event("ignored", message=f"nothing to re-record: {reason}")
            return
        episode, frames, had_previous = self._last_save
        self._last_save = None
        staged_directory.revert(self.target, had_previous)
        self.log.info(f"episode {episode} removed ({frames} frames), to be recorded again")
        self.on_event(
            "removed",
            episode=episode,
            frames=frames,
            episodes=episode,
            message=f"removed episode {episode} ({frames} frames) from {self.target}; recording it again",
        )

    def _drop_dataset(self) -> None:
        if self._dataset is not None:
            try:
                self._dataset.stop_image_writer()
                self._dataset.clear_episode_buffer(delete_images=False)
                self._dataset.finalize()
            except Exception:  # the staging copy is deleted below whatever state it is in
                pass
            self._dataset = self._images = None
        staged_directory.discard(self.target)
        self._frames = 0

    def _clear_cache(self) -> None:
        for entry in Path(self._cache).iterdir():
            if entry.name != private_cache.LOCK_NAME:
                shutil.rmtree(entry, ignore_errors=True)

    def _open(self):
        """The LeRobotDataset to write the next episode into, in a fresh staging copy."""
        from lerobot.datasets.lerobot_dataset import LeRobotDataset

        from joshua_runtime.ai.checked_image_writer import CheckedImageWriter

        if self._features is None:
            raise JoshuaError("a frame arrived before the dataset features were known")
        staging = staged_directory.prepare(self.target)
        repo_id = f"local/{self.target.name}"
        if not (staging / "meta" / "info.json").is_file():
            dataset = LeRobotDataset.create(
                repo_id,
                self.fps,
                self._features,
                root=staging,
                robot_type=self.robot_type,
                use_videos=self.use_videos,
                video_backend="pyav",
                vcodec=VIDEO_CODEC,
                streaming_encoding=self.use_videos,
            )
        else:
            self._check_compatible(staging)
            dataset = LeRobotDataset(
                repo_id,
                root=staging,
                video_backend="pyav",
                vcodec=VIDEO_CODEC,
                streaming_encoding=self.use_videos,
            )
        if not self.use_videos:
            self._images = dataset.image_writer = CheckedImageWriter(IMAGE_WRITER_THREADS)
        return dataset

    def _check_compatible(self, staging: Path) -> None:
        info = json.loads((staging / "meta" / "info.json").read_text())
        if info.get("fps") != self.fps:
            raise SettingsError(f"dataset {self.target} was recorded at {info.get('fps')} fps, not {self.fps}")
        existing = {key: _comparable(value) for key, value in info["features"].items() if key not in _DEFAULT_FEATURES}
        wanted = {key: _comparable(value) for key, value in self._features.items()}
        if existing != wanted:
            raise SettingsError(
                f"dataset {self.target} has features {sorted(existing)} of other types, shapes or names "
                f"than this recording ({sorted(wanted)}); choose another output_directory"
            )


def _comparable(feature: dict) -> tuple:
    return feature["dtype"], tuple(feature["shape"]), tuple(feature.get("names") or ())
