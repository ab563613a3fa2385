"""The instruction a language-conditioned policy (SmolVLA) follows, and where an INFERENCE node gets it.

The node starts with the task its policy was trained on when the training dataset had exactly one
(`tasks` in joshua_policy.json, written by `joshua-train imitation`), and takes a new instruction from
every std_msgs/msg/String on `/<node name>/task` (TASK_TOPIC: reliable, the last one kept, so a
node that starts after it was sent still gets it), e.g.
`joshua-topic pub /policy/task std_msgs/msg/String '{data: "pick the red cube"}'`. A new instruction
resets the policy (actions queued for the old one are dropped). Until it has an instruction the
node publishes nothing and says why.
"""

from pathlib import Path

from joshua_runtime.ai import saved_policy

TASK_TOPIC = "~/task"
LANGUAGE_POLICY_TYPES = ("smolvla",)


def follows_instructions(policy_type: str) -> bool:
    return policy_type in LANGUAGE_POLICY_TYPES


def trained_task(policy_dir: Path) -> str:
    """The one task of the policy's training dataset, or "" when it had several or none is recorded."""
    metadata = saved_policy.read(policy_dir) or {}
    tasks = metadata.get("tasks") or []
    return tasks[0] if len(tasks) == 1 and isinstance(tasks[0], str) else ""


def task_qos():
    """Reliable, the last instruction kept for nodes that subscribe later (TRANSIENT_LOCAL)."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
