"""The dashboard's ROS side: subscribes to the robot's topics in a thread of its own and feeds the broadcaster.

Subscriptions are BEST_EFFORT with a short queue, so the dashboard never holds a publisher back;
camera frames are JPEG-encoded only while a browser is connected, at most IMAGE_MAX_FPS per topic.
It also sends the recorder's episode commands and follows its answers (see ai/episode_protocol.py).
"""

import json
import threading
import time
from pathlib import Path

import rclpy
from rclpy.experimental import EventsExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from joshua_runtime.ai import episode_protocol
from joshua_runtime.dashboard import cdr, frames
from joshua_runtime.dashboard.api_schema import event_kind
from joshua_runtime.dashboard.robot_view import IMAGE, JOINTS, SCAN, Inference, RobotView
from joshua_runtime.messages import message_class
from joshua_runtime.ros_node import create_ros_node
from joshua_runtime.ros_teardown import leave_ros

REPORT_PERIOD_S = 1.0
IMAGE_MAX_FPS = 30.0
JOINTS_MAX_HZ = 60.0
# An inference input older than this counts as stale (the inference node's own threshold).
INPUT_STALE_AFTER_S = 0.5
SPIN_SLICE_S = 0.05
SENSOR_QOS = QoSProfile(depth=2, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
COMMAND_QOS = QoSProfile(
    depth=episode_protocol.COMMAND_QOS_DEPTH,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)
# The event of each stream kind the page draws (named after the kind); the other streams only count messages.
_EVENT_MAKERS = {
    event_kind(JOINTS): frames.joint_state_event,
    event_kind(IMAGE): frames.image_event,
    event_kind(SCAN): frames.scan_event,
}
_MIN_PERIOD_S = {JOINTS: 1.0 / JOINTS_MAX_HZ, IMAGE: 1.0 / IMAGE_MAX_FPS, SCAN: 0.0}
RATES_EVENT = event_kind("rates")
RECORDER_EVENT = event_kind("recorder")
INFERENCE_EVENT = event_kind("inference")


def saved_episodes(output_directory: str) -> int | None:
    """How many episodes the dataset at `output_directory` holds (None when it has none yet)."""
    try:
        info = json.loads((Path(output_directory).expanduser() / "meta" / "info.json").read_text())
        return int(info.get("total_episodes", 0))
    except (OSError, ValueError, TypeError):
        return None


def recorder_event(recorder: str, status: dict, progress: dict | None, episodes_saved: int) -> dict:
    """The `recorder` event of a recorder node, from its last episode state (empty when none came yet) and
    its last progress report (None when none came yet)."""
    return {
        "node": recorder,
        "known": bool(status),
        "recording": progress["phase"] == "recording" if progress else bool(status.get("recording")),
        "event": status.get("event", ""),
        "message": status.get("message", ""),
        "episodes_saved": episodes_saved,
        "progress": progress,
    }


def inference_event(inference: Inference, rate_hz: float, stale_inputs: list[str]) -> dict:
    """The `inference` event of an inference node: the rate of its output topic and its stale inputs."""
    return {
        "node": inference.node,
        "model": inference.model,
        "configured_rate_hz": inference.rate_hz,
        "rate_hz": rate_hz,
        "stale_inputs": stale_inputs,
    }


class Telemetry:
    """An rclpy node in a context of its own, spun by a daemon thread until `close()`."""

    def __init__(self, view: RobotView, broadcaster, node_name: str = "dashboard"):
        self.view = view
        self.broadcaster = broadcaster
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = create_ros_node(node_name, context=self.context)
        self.executor = EventsExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.counts = {stream.topic: 0 for stream in view.streams}
        self.last_received: dict[str, float] = {}
        self.last_sent: dict[str, float] = {}
        self.recorder_status: dict[str, dict] = {}
        self.recorder_progress: dict[str, dict] = {}
        self.subscriptions = [self._subscribe(stream) for stream in view.streams]
        from std_msgs.msg import String

        self.command_publishers = {
            r.node: self.node.create_publisher(String, r.command_topic, COMMAND_QOS) for r in view.recorders
        }
        self.status_subscriptions = [
            self.node.create_subscription(
                String, r.status_topic, self._recorder_callback(r.node), episode_protocol.state_qos()
            )
            for r in view.recorders
        ] + [
            self.node.create_subscription(
                String, r.progress_topic, self._progress_callback(r.node), episode_protocol.progress_qos()
            )
            for r in view.recorders
        ]
        self.timer = self.node.create_timer(REPORT_PERIOD_S, self._report)
        self._last_report = time.monotonic()
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, name="dashboard-ros", daemon=True)

    def start(self) -> None:
        self.thread.start()

    def close(self) -> None:
        self._stop.set()
        if self.thread.is_alive():
            self.thread.join()
        leave_ros(self.executor, self.node, self.context)

    def send_episode_command(self, recorder: str, command: str) -> None:
        """Publish an episode command (`start TASK`, `stop`, `next` ...) to a recorder node."""
        from std_msgs.msg import String

        self.command_publishers[recorder].publish(String(data=command))

    def _spin(self) -> None:
        while not self._stop.is_set() and self.context.ok():
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)

    def _subscribe(self, stream):
        """A subscription that takes messages serialized, as DDS delivers them: counting one costs no decoding,
        and only those that become events are decoded (a 640x480 frame nobody watches never is), joint
        states and images straight from their bytes (cdr.py)."""
        from rclpy.serialization import deserialize_message

        make_event = _EVENT_MAKERS.get(stream.kind)
        min_period = _MIN_PERIOD_S.get(stream.kind, 0.0)
        message_type = message_class(stream.message_type)

        def receive(serialized: bytes) -> None:
            now = time.monotonic()
            self.counts[stream.topic] += 1
            self.last_received[stream.topic] = now
            if make_event is None or now - self.last_sent.get(stream.topic, 0.0) < min_period:
                return
            if stream.kind == IMAGE and self.broadcaster.client_count == 0:
                return
            self.last_sent[stream.topic] = now
            try:
                message = cdr.decode(stream.message_type, serialized)
                if message is None:
                    message = deserialize_message(serialized, message_type)
                data = make_event(stream.topic, message)
            except ValueError as exc:
                self.node.get_logger().warning(f"{stream.topic}: {exc}", throttle_duration_sec=5.0)
                return
            self.broadcaster.publish(f"{stream.kind}:{stream.topic}", stream.kind, data)

        return self.node.create_subscription(message_type, stream.topic, receive, SENSOR_QOS, raw=True)

    def _recorder_callback(self, recorder: str):
        def receive(message) -> None:
            state = episode_protocol.decode(message.data)
            if state is not None:
                self.recorder_status[recorder] = state
                self._publish_recorder(recorder)

        return receive

    def _progress_callback(self, recorder: str):
        def receive(message) -> None:
            progress = episode_protocol.decode_progress(message.data)
            if progress is not None:
                self.recorder_progress[recorder] = progress
                self._publish_recorder(recorder)

        return receive

    def _publish_recorder(self, recorder: str) -> None:
        spec = next(r for r in self.view.recorders if r.node == recorder)
        status = self.recorder_status.get(recorder, {})
        progress = self.recorder_progress.get(recorder)
        self.broadcaster.publish(
            f"{RECORDER_EVENT}:{recorder}",
            RECORDER_EVENT,
            recorder_event(recorder, status, progress, saved_episodes(spec.output_directory) or 0),
        )

    def _report(self) -> None:
        now = time.monotonic()
        elapsed = max(now - self._last_report, 1e-3)
        self._last_report = now
        rates = {topic: round(count / elapsed, 1) for topic, count in self.counts.items()}
        for topic in self.counts:
            self.counts[topic] = 0
        self.broadcaster.publish(RATES_EVENT, RATES_EVENT, {"rates": rates})
        for inference in self.view.inferences:
            stale = [
                t for t in inference.inputs if now - self.last_received.get(t, float("-inf")) > INPUT_STALE_AFTER_S
            ]
            self.broadcaster.publish(
                f"{INFERENCE_EVENT}:{inference.node}",
                INFERENCE_EVENT,
                inference_event(inference, rates.get(inference.output, 0.0), stale),
            )
        for recorder in self.view.recorders:
            self._publish_recorder(recorder.node)
