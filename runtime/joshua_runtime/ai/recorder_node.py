"""DATA_SUBSCRIBER node: record a JointState topic and sensor inputs into a LeRobotDataset v3.0.

Settings used: `topic` (sensor_msgs/msg/JointState, recorded as `action`), `inputs` (Image and
JointState topics, recorded as `observation.images.<key>` / `observation.state`, see `features.py`),
`rate_hz` (frames per second, rounded to an integer), `output_directory`, `output_format`:
- `lerobot`: images are video features (AV1 mp4 files, encoded while recording);
- `parquet`: the same dataset with images stored as image features (PNG inside the parquet files),
  no video files. Without Image inputs both formats are identical.
`units` (SI, LEROBOT, LEROBOT_RANGE) with `calibration_file`: the convention of the joint values
(lerobot_units.py). `episode_time_s` and `reset_time_s`: the episode workflow (episode_session.py).

Frames: at every tick the latest message of each topic is held; when one has not published yet or
its last message is older than `SAMPLE_STALE_AFTER_S`, the frame is skipped and reported (throttled).

Episodes: one starts when the node starts. Commands on the std_msgs/String topic `~/episode`
(i.e. `/<node name>/episode`) control them (`start [task]`, `stop`, `discard`, `next`, `rerecord`);
the node answers each on `~/episode_state` and reports its progress on `~/episode_progress`
(episode_protocol.py; `joshua-episode` is the command-line client). SIGINT/SIGTERM save the episode
in progress before the process exits; when that waits for the writer still loading LeRobot, the node asks its
process manager for more time (EXTEND_TIMEOUT_USEC), so the save is not cut short by the SIGINT grace. See `episode_writer.py` for the crash guarantees.

The node is ready (its "ready:" line, READY=1) as soon as it has subscribed: the dataset is written by a
process of its own (writer_process.py), which imports LeRobot meanwhile; frames wait for it in a queue.

output_format `mcap` records a ROS bag instead: constructing a RecorderNode with it gives a
BagRecorderNode (joshua_runtime.bags), the registry's one class per type dispatching by format.
"""

import json
import threading
from pathlib import Path

from joshua_core.models import BAG_FORMAT, OUTPUT_FORMATS
from joshua_runtime.ai import episode_protocol as protocol
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.episode_session import IDLE, EpisodeSession
from joshua_runtime.ai.frame_sampler import FrameSampler, FrameUnavailable
from joshua_runtime.ai.latest_samples import LatestSamples
from joshua_runtime.ai.lerobot_units import SI, JointUnits
from joshua_runtime.ai.writer_process import WriterProcess
from joshua_runtime.errors import SettingsError
from joshua_runtime.graph import with_discovered_types
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks

SAMPLE_STALE_AFTER_S = 0.5
PROBLEM_LOG_PERIOD_S = 2.0


def check_output_directory(directory: Path, fps: int) -> int:
    """The episodes the dataset at `directory` holds (0 when there is none yet); refuse a directory that
    holds something else than a LeRobot dataset, or one recorded at another fps."""
    info = directory / "meta" / "info.json"
    if info.is_file():
        try:
            meta = json.loads(info.read_text())
        except (OSError, ValueError) as exc:
            raise SettingsError(f"output_directory {directory}: unreadable {info}: {exc}") from exc
        if meta.get("fps") != fps:
            raise SettingsError(
                f"output_directory {directory} holds a dataset recorded at {meta.get('fps')} fps, not {fps}"
            )
        return int(meta.get("total_episodes") or 0)
    if directory.is_dir() and any(directory.iterdir()):
        raise SettingsError(f"output_directory {directory} is not empty and holds no LeRobot dataset")
    if directory.exists() and not directory.is_dir():
        raise SettingsError(f"output_directory {directory} is not a directory")
    return 0


class RecorderNode(JoshuaNode):
    """Samples its topics at rate_hz into episodes written by a WriterProcess."""

    def __new__(cls, settings, ros_node):
        if cls is RecorderNode and settings.output_format == BAG_FORMAT:
            from joshua_runtime.bags.bag_recorder_node import BagRecorderNode

            return BagRecorderNode(settings, ros_node)  # not a RecorderNode, so __init__ is not run again
        return super().__new__(cls)

    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        if topic.message_type != keys.JOINT_STATE:
            raise SettingsError(f"{self.name}: the recorded topic must be {keys.JOINT_STATE} (it becomes the action)")
        inputs = with_discovered_types(self.ros, self.settings.inputs)
        keys.check_inputs(self.name, inputs)
        output_format = self.settings.output_format
        if output_format not in OUTPUT_FORMATS:
            raise SettingsError(f"output_format {output_format!r} is not one of {', '.join(OUTPUT_FORMATS)}")
        if not self.settings.output_directory:
            raise SettingsError(f"{self.name}: output_directory is empty")
        self.fps = max(1, round(1.0 / settings_checks.period_s(self.settings)))
        episodes = check_output_directory(Path(self.settings.output_directory).expanduser(), self.fps)
        units = JointUnits(self.settings.units or SI, self.settings.calibration_file)
        use_videos = output_format == "lerobot"
        from std_msgs.msg import String

        self.message = String
        self.state_publisher = self.ros.create_publisher(String, protocol.STATE_TOPIC, protocol.state_qos())
        self.progress_publisher = self.ros.create_publisher(String, protocol.PROGRESS_TOPIC, protocol.progress_qos())
        self.state_lock = threading.Lock()  # the ROS thread and the writer's event thread both publish states
        self.state_seq = 0
        self.writer = WriterProcess(
            self.settings.output_directory, self.fps, self.settings.robot, use_videos, self.log, self._writer_event
        )
        self.session = EpisodeSession(
            self.writer,
            self._publish_state,
            self.log,
            self.settings.robot or self.name,
            self.settings.episode_time_s,
            self.settings.reset_time_s,
            episodes,
        )
        self.sampler = FrameSampler(topic.name, inputs, use_videos, units)
        self.samples = LatestSamples(self.sampler.topic_names)
        self.subscriptions = [self.subscription(t, self.samples.callback(t.name)) for t in [topic, *inputs]]
        self.commands = self.ros.create_subscription(
            String, protocol.COMMAND_TOPIC, self._command, protocol.COMMAND_QOS_DEPTH
        )
        self.session.begin()
        self.timer = self.ros.create_timer(1.0 / self.fps, self._tick)
        self.progress_timer = self.ros.create_timer(protocol.PROGRESS_PERIOD_S, self._publish_progress)
        units_note = f", joint values in {units.units} units" if units.converts else ""
        self.announce_ready(
            f"recording {len(self.sampler.topic_names)} topics at {self.fps} fps into "
            f"{self.settings.output_directory} ({output_format}{units_note}); episode commands on "
            f"{self.ros.resolve_topic_name(protocol.COMMAND_TOPIC)}"
        )
        self._publish_state("ready", message=f"ready, recording into {self.settings.output_directory}")
        self._publish_progress()

    def _writer_event(self, event: str, **details) -> None:
        """Called from the writer's event thread: say when LeRobot is loaded, answer episode commands."""
        if event == "opened":
            self.log.info(f"dataset writer ready {details['after_s']:.2f} s after the start (LeRobot loaded)")
            return
        if event in ("saved", "removed"):
            self.session.episodes = details["episodes"]
        self._publish_state(event, **details)

    def _publish_state(self, event: str, **details) -> None:
        """An event, then a progress report that names it as the last (a client that joins knows when the
        kept events have all reached it)."""
        with self.state_lock:
            self.state_seq += 1
            state = {"seq": self.state_seq, "event": event, "recording": self.session.recording, **details}
            self.state_publisher.publish(self.message(data=protocol.encode(state)))
            self._publish_progress_locked()

    def _publish_progress(self) -> None:
        with self.state_lock:
            self._publish_progress_locked()

    def _publish_progress_locked(self) -> None:
        progress = self.session.progress(self.writer.opened.is_set(), self.state_seq)
        self.progress_publisher.publish(self.message(data=json.dumps(progress, sort_keys=True)))

    def _command(self, msg) -> None:
        phase = self.session.phase
        self.session.command(msg.data)
        if self.session.phase != phase:
            self._publish_progress()

    def _tick(self) -> None:
        if self.writer.error is not None:
            self.error_reported = True
            self.session.phase = IDLE  # the writer ended the episode as lost: nothing left to save at close
            raise self.writer.error
        phase = self.session.phase
        self.session.tick()
        if self.session.phase != phase:
            self._publish_progress()
        if not self.session.recording:
            return
        problems = self.samples.problems(SAMPLE_STALE_AFTER_S)
        first = self.sampler.features is None
        if not problems:
            try:
                frame = self.sampler.frame(self.samples.message)
            except FrameUnavailable as exc:
                problems = [str(exc)]
        if problems:
            self.session.frame_skipped()
            self.log.warning(f"frame skipped: {'; '.join(problems)}", throttle_duration_sec=PROBLEM_LOG_PERIOD_S)
            return
        if first:
            self.writer.configure(self.sampler.features)
        self.writer.add_frame(frame)
        self.session.frame_recorded()

    def close(self) -> None:
        for name in ("timer", "progress_timer"):
            timer = getattr(self, name, None)
            if timer is not None:
                timer.cancel()
        writer = getattr(self, "writer", None)
        if writer is None:
            return
        session = getattr(self, "session", None)
        if session is not None:
            session.close()
        writer.close(self.notifier)  # a save that waits for LeRobot asks the supervisor for more time
        if writer.error is not None and not getattr(self, "error_reported", False):
            raise writer.error
