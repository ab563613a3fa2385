"""INFERENCE node: serve a LeRobot policy (ACT, Diffusion, SmolVLA) or a `joshua-train rl` PPO policy as a ROS 2 node.

Settings used: `model_path` (a policy directory saved by LeRobot, or `registry:NAME[@REV]`),
`policy_type` (optional check against the saved config), `device` (`cpu` / `cuda`), `inputs`
(Image and JointState topics, mapped to policy features as described in `observation_mapper.py`),
`topic` (sensor_msgs/msg/JointState actions; a PPO reach policy publishes goal angles of
the four arm joints and aims at the `goal` of its joshua_policy.json, see ai/ppo_runner.py; or
trajectory_msgs/msg/JointTrajectory action chunks, see below), `joint_names` (names of the published
joints; when empty, the policy's action feature names without `.pos`), `rate_hz` (inference and publish
rate; with action chunks, the rate of the chunk's actions, i.e. of the dataset the policy learnt from).

JointState: at each tick the policy's `select_action` runs in the node's loop and one action is
published, stamped with the observation's time (the oldest header stamp of the inputs used).
SmolVLA follows an instruction: the task it was trained on, or the last std_msgs/String sent to
`/<node name>/task` (instruction.py).
JointTrajectory (ACT, Diffusion, SmolVLA): the model runs in a background thread (`chunked_inference.py`) on the
newest observation, and each call's whole chunk is published once, header stamped with the
observation's time; the actuator executes it at its own rate while the next call runs.

The policy is loaded and warmed up (one inference on a blank observation, then reset) in a
background thread while the node keeps answering signals, torch's worker threads set to sleep while
they wait (`cpu_threads.py`); the node announces itself ready (its "ready:" line and READY=1 to the
process manager) after the warm-up.
At each tick, when an input has not published yet or its last message is older than
`INPUT_STALE_AFTER_S`, nothing is published and the reason is logged (throttled); when inputs come
back, the policy is reset first so that actions queued before the gap are never executed.
"""

import math
import threading
import time

from joshua_core.message_types import JOINT_COMMAND_TYPES
from joshua_runtime.ai import cpu_threads, data_only, instruction, model_files, registry, saved_policy
from joshua_runtime.ai import features as keys
from joshua_runtime.ai.chunked_inference import ChunkedInference
from joshua_runtime.ai.latest_samples import LatestSamples
from joshua_runtime.ai.ros_arrays import joint_state, joint_trajectory, stamp_seconds, time_message
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.graph import with_discovered_types
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.trajectory_follower import is_trajectory, now_s

INPUT_STALE_AFTER_S = 0.5
PROBLEM_LOG_PERIOD_S = 2.0


def resolve_model_path(model_path: str):
    """The policy directory named by a settings `model_path` (a directory or `registry:NAME[@REV]`), checked
    to be data (data_only.py) and, for a registry entry, to hold exactly the files it was imported with."""
    if not model_path:
        raise SettingsError("model_path is empty")
    try:
        if registry.is_reference(model_path):
            entry = registry.resolve(model_path)
            data_only.check(entry.path)
            registry.verify(entry)
            return registry.policy_files(entry.path)[0]
        policy_dir = registry.policy_files(model_path)[0]
        data_only.check(policy_dir)
        return policy_dir
    except registry.RegistryError as exc:
        raise SettingsError(str(exc)) from exc


def action_joint_names(joint_names: list[str], size: int, feature_names: list[str] | None) -> list[str]:
    """Names of the published joints: `joint_names` when set, else the policy's action names without `.pos`."""
    if joint_names:
        if len(joint_names) != size:
            raise SettingsError(f"joint_names has {len(joint_names)} names but the policy outputs {size} actions")
        return list(joint_names)
    if feature_names and len(feature_names) == size:
        return [keys.joint_name(name) for name in feature_names]
    raise SettingsError(f"the policy does not record its {size} action names; set joint_names on the INFERENCE node")


class InferenceNode(JoshuaNode):
    """Subscribes to sensor inputs and publishes JointState actions (one per tick) or JointTrajectory chunks."""

    ready_later = True  # ready once the policy is loaded and warmed up

    def start(self) -> None:
        topic = settings_checks.topic(self.settings)
        if topic.message_type not in JOINT_COMMAND_TYPES:
            raise SettingsError(f"{self.name}: the action topic must be {' or '.join(JOINT_COMMAND_TYPES)}")
        self.chunked = is_trajectory(topic)
        self.inputs = inputs = with_discovered_types(self.ros, self.settings.inputs)
        if not inputs:
            raise SettingsError(f"{self.name}: no input topics")
        keys.check_inputs(self.name, inputs)
        self.policy_dir = resolve_model_path(self.settings.model_path)
        saved_type = registry.policy_files(self.policy_dir)[1]
        supported = (*model_files.SUPPORTED_POLICY_TYPES, saved_policy.KIND_PPO)
        if saved_type not in supported:
            raise SettingsError(f"policy type {saved_type!r} is not supported (supported: {', '.join(supported)})")
        self.policy_type = saved_type
        if self.chunked and saved_type == saved_policy.KIND_PPO:
            raise SettingsError(
                f"{self.name}: a {saved_type} policy gives one action per call; action chunks "
                f"({topic.message_type}) need a LeRobot policy ({', '.join(model_files.SUPPORTED_POLICY_TYPES)})"
            )
        wanted = self.settings.policy_type
        if wanted and wanted.lower() != saved_type:
            raise SettingsError(f"policy_type is {wanted!r} but the policy in {self.policy_dir} is {saved_type!r}")
        self.rate_hz = 1.0 / settings_checks.period_s(self.settings)
        self.task = ""
        if instruction.follows_instructions(saved_type):
            self.task = instruction.trained_task(self.policy_dir)
            from std_msgs.msg import String

            self.task_subscription = self.ros.create_subscription(
                String, instruction.TASK_TOPIC, self._on_task, instruction.task_qos()
            )
        self.samples = LatestSamples([t.name for t in inputs])
        self.subscriptions = [self.subscription(t, self.samples.callback(t.name)) for t in inputs]
        self.action_publisher = self.publisher(topic)
        self.runner = None
        self.mapper = None
        self.worker = None
        self.joint_names: list[str] = []
        self.ready = threading.Event()
        self.load_error: BaseException | None = None
        self.inputs_interrupted = False
        self.published = 0
        self.started_s = time.monotonic()
        self.loader = threading.Thread(target=self._load, name="policy-loader", daemon=True)
        self.loader.start()
        self.timer = self.ros.create_timer(1.0 / self.rate_hz, self._tick)

    def _load(self) -> None:
        try:
            not_prepared = cpu_threads.prepare()  # before torch is imported by the runner
            if not_prepared:
                self.log.warning(not_prepared)
            from joshua_runtime.ai.observation_mapper import ObservationMapper

            if self.policy_type == saved_policy.KIND_PPO:
                from joshua_runtime.ai.ppo_runner import PpoRunner

                runner = PpoRunner(self.policy_dir, self.rate_hz)
                names = runner.feature_names
            else:
                from joshua_runtime.ai.policy_runner import PolicyRunner

                runner = PolicyRunner(self.policy_dir, self.settings.device)
                names = model_files.feature_names(self.policy_dir)
            self.joint_names = action_joint_names(
                list(self.settings.joint_names), runner.shapes.action_size, names.get(keys.ACTION)
            )
            self.mapper = ObservationMapper(
                self.name,
                self.inputs,
                runner.shapes.images,
                runner.shapes.state_size,
                names.get(keys.STATE),
            )
            for unused in self.mapper.unused_topics:
                self.log.warning(f"input {unused} feeds no policy feature and is ignored")
            warm_up_s = runner.warm_up(self.task)
            if self.chunked:
                self.worker = ChunkedInference(runner, self._publish_chunk, 1.0 / self.rate_hz, self.log, self._now_s)
                self.worker.start()
            self.runner = runner
            self.ready.set()
            self.announce_ready(
                f"{self.policy_type} policy from {self.policy_dir} on {runner.device} "
                f"(load+warm-up {time.monotonic() - self.started_s:.2f} s, first inference {warm_up_s:.3f} s), "
                f"{len(self.joint_names)} joints"
            )
        except JoshuaError as exc:
            self.load_error = exc
        except Exception as exc:  # a broken checkpoint surfaces as many library exception types
            self.load_error = JoshuaError(f"cannot load policy from {self.policy_dir}: {type(exc).__name__}: {exc}")

    def _tick(self) -> None:
        if self.load_error is not None:
            error, self.load_error = self.load_error, None
            raise error
        if not self.ready.is_set():
            return
        problems = self.samples.problems(INPUT_STALE_AFTER_S)
        if instruction.follows_instructions(self.policy_type) and not self.task:
            problems = [
                *problems,
                f"no instruction yet: publish one on {self.ros.resolve_topic_name(instruction.TASK_TOPIC)}",
            ]
        if problems:
            self._hold("; ".join(problems))
            return
        if self.worker is not None:
            if self.worker.error is not None:
                error = self.worker.error
                raise JoshuaError(f"inference failed: {type(error).__name__}: {error}") from error
            if not self.worker.idle():
                return
        from joshua_runtime.ai.observation_mapper import ObservationUnavailable

        try:
            observation = self.mapper.observation(self.samples.message)
        except ObservationUnavailable as exc:
            self._hold(str(exc))
            return
        if self.chunked:
            self._offer(observation)
            return
        if self.inputs_interrupted:
            self.runner.reset()
            self.inputs_interrupted = False
        try:
            action = self.runner.act(observation, self.task)
        except Exception as exc:
            raise JoshuaError(f"inference failed: {type(exc).__name__}: {exc}") from exc
        if not all(math.isfinite(float(v)) for v in action):
            self._hold("the policy returned a non-finite action")
            return
        self.action_publisher.publish(joint_state(self.joint_names, action, time_message(self._observation_s())))
        self._count_published("action")

    def _offer(self, observation) -> None:
        """Hand the observation to the background inference thread (it is idle)."""
        if self.inputs_interrupted:
            self.worker.interrupt()
            self.inputs_interrupted = False
        self.worker.offer(observation, self._observation_s(), self.task)

    def _on_task(self, message) -> None:
        """A new instruction: follow it from the next tick, after a reset (queued actions were for the old one)."""
        if message.data == self.task:
            return
        self.task = message.data
        self.inputs_interrupted = True
        self.log.info(f"instruction: {self.task!r}")

    def _publish_chunk(self, chunk, stamp_s: float) -> None:
        """Called by the inference thread with each call's chunk (steps x joints)."""
        if chunk.shape[1] != len(self.joint_names):
            raise JoshuaError(
                f"the policy returned chunks of {chunk.shape[1]} actions for {len(self.joint_names)} joints"
            )
        self.action_publisher.publish(joint_trajectory(self.joint_names, chunk, stamp_s, 1.0 / self.rate_hz))
        self._count_published("action chunk")

    def _count_published(self, what: str) -> None:
        self.published += 1
        if self.published == 1:
            self.log.info(f"first {what} published {time.monotonic() - self.started_s:.2f} s after start")

    def _now_s(self) -> float:
        return now_s(self.ros)

    def _observation_s(self) -> float:
        """When the observation was taken: the oldest header stamp of the inputs (now when none is stamped)."""
        stamps = [stamp_seconds(self.samples.message(t.name)) for t in self.inputs]
        stamped = [stamp for stamp in stamps if stamp > 0]
        return min(stamped) if stamped else self._now_s()

    def _hold(self, reason: str) -> None:
        """Publish nothing this tick, remember the gap and say why (at most every PROBLEM_LOG_PERIOD_S)."""
        self.inputs_interrupted = True
        self.log.warning(f"no action: {reason}", throttle_duration_sec=PROBLEM_LOG_PERIOD_S)

    def close(self) -> None:
        timer = getattr(self, "timer", None)
        if timer is not None:
            timer.cancel()
        if getattr(self, "worker", None) is not None:
            self.worker.stop()
