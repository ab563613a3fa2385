"""A ROS client of one recorder's episode topics: send a command, wait for its answer, follow its progress.

Used by `joshua-episode` (its one-shot commands, `status` and `keys`). The state and progress topics keep
their last message for late subscribers (episode_protocol.py), so a client learns the recorder's current
state and progress as soon as it has discovered it.
"""

import os
import time

from joshua_runtime.ai import episode_protocol as protocol
from joshua_runtime.ros_node import create_ros_node

SPIN_SLICE_S = 0.05


class RecorderClient:
    """One rclpy context and node in `domain` (None: ROS_DOMAIN_ID) talking to the recorder `node_name`."""

    def __init__(self, node_name: str, domain: int | None):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from std_msgs.msg import String

        self.node_name = node_name
        self.message = String
        self.context = rclpy.Context()
        rclpy.init(context=self.context, **({"domain_id": domain} if domain is not None else {}))
        self.node = create_ros_node(f"joshua_episode_{os.getpid()}", context=self.context)
        self.states: list[dict] = []
        self.progress: dict | None = None
        self.node.create_subscription(
            String, protocol.topic(node_name, protocol.STATE_TOPIC), self._state, protocol.state_qos()
        )
        self.node.create_subscription(
            String, protocol.topic(node_name, protocol.PROGRESS_TOPIC), self._progress, protocol.progress_qos()
        )
        self.publisher = self.node.create_publisher(
            String, protocol.topic(node_name, protocol.COMMAND_TOPIC), protocol.COMMAND_QOS_DEPTH
        )
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)

    def __enter__(self):
        return self

    def __exit__(self, *_exc) -> None:
        self.close()

    def close(self) -> None:
        import rclpy

        self.executor.shutdown(timeout_sec=0)
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def _state(self, msg) -> None:
        state = protocol.decode(msg.data)
        if state is not None:
            self.states.append(state)

    def _progress(self, msg) -> None:
        progress = protocol.decode_progress(msg.data)
        if progress is not None:
            self.progress = progress

    def spin_until(self, condition, seconds: float) -> bool:
        deadline = time.monotonic() + seconds
        while not condition() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=SPIN_SLICE_S)
        return bool(condition())

    def spin_once(self, seconds: float = SPIN_SLICE_S) -> None:
        self.executor.spin_once(timeout_sec=seconds)

    def found(self, timeout_s: float) -> bool:
        """Whether the recorder was discovered: it takes commands, and its kept events have arrived up to the
        last one its progress report names (an event kept from before must not pass for an answer)."""
        return self.spin_until(lambda: self.publisher.get_subscription_count() > 0 and self._caught_up(), timeout_s)

    def _caught_up(self) -> bool:
        return self.progress is not None and self._last_seq() >= self.progress.get("seq", 0) and bool(self.states)

    def _last_seq(self) -> int:
        return max((state["seq"] for state in self.states), default=0)

    def wait_progress(self, timeout_s: float) -> dict | None:
        self.spin_until(lambda: self.progress is not None, timeout_s)
        return self.progress

    def send(self, text: str):
        """Publish a command; returns a function that gives its answer once it has come (else None)."""
        baseline = max(self._last_seq(), (self.progress or {}).get("seq", 0))
        answers = protocol.ANSWERS[text.split(" ", 1)[0]]
        self.publisher.publish(self.message(data=text))
        return lambda: next((s for s in self.states if s["seq"] > baseline and s["event"] in answers), None)

    def exchange(self, text: str, timeout_s: float) -> dict:
        """Send a command to a found recorder and wait for its answer ({} when none came in time)."""
        answer = self.send(text)
        self.spin_until(answer, timeout_s)
        return answer() or {}


def describe(node_name: str, progress: dict) -> str:
    """One line saying what the recorder is doing, e.g.
    `rec: recording episode 3 (task: pick): 12.3 s of 30 s, 368 frames (2 skipped); 3 episodes saved`."""
    phase, saved = progress["phase"], progress["episodes"]
    elapsed, remaining = progress["elapsed_s"], progress["remaining_s"]
    if phase == "recording":
        length = f"{elapsed:.1f} s of {elapsed + remaining:.0f} s" if remaining is not None else f"{elapsed:.1f} s"
        skipped = f" ({progress['skipped']} skipped)" if progress["skipped"] else ""
        what = f"recording episode {saved} (task: {progress['task']}): {length}, {progress['frames']} frames{skipped}"
    elif phase == "resetting":
        what = f"resetting, {remaining:.1f} s left before episode {saved}"
    else:
        what = "idle"
    loading = "; dataset writer loading LeRobot" if progress.get("writer") == "loading" else ""
    return f"{node_name}: {what}; {saved} episode{'s' if saved != 1 else ''} saved{loading}"
