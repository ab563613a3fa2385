"""How a recorder is told to start, stop or discard episodes, and how it answers, over two std_msgs/String topics.

Commands go to `/<recorder>/episode`: `start [task]`, `stop`, `discard`. The recorder answers on
`/<recorder>/episode_state` with one JSON object per event, e.g.
`{"seq": 4, "event": "saved", "recording": false, "episode": 3, "frames": 412, "episodes": 4,
"message": "saved episode 3 (412 frames) in /data/pick"}`. `seq` counts the recorder's events; the
topic keeps the last one for late subscribers (TRANSIENT_LOCAL), so a client learns the current state
as soon as it connects, then waits for an event with a higher `seq` that answers its command.

Events: `ready` (the recorder is ready and recording its first episode), `started`, `saved`, `empty`
(an episode without frames: nothing saved), `discarded`, `ignored` (a command that did not apply, e.g.
`stop` with no episode recording), `failed` (the episode could not be saved).
"""

import json

COMMAND_TOPIC = "~/episode"
STATE_TOPIC = "~/episode_state"
COMMAND_QOS_DEPTH = 10
COMMANDS = ("start", "stop", "discard")
# The events that answer each command (the first ones are success).
ANSWERS = {
    "start": ("started", "ignored"),
    "stop": ("saved", "empty", "ignored", "failed"),
    "discard": ("discarded", "ignored", "failed"),
}
SUCCESS = ("started", "saved", "empty", "discarded")


def state_qos():
    """The state topic's QoS: reliable, the last event kept for subscribers that join later."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )


def encode(state: dict) -> str:
    return json.dumps(state, sort_keys=True)


def decode(text: str) -> dict | None:
    """The state object of a message, or None when it is not one."""
    try:
        state = json.loads(text)
    except ValueError:
        return None
    return state if isinstance(state, dict) and isinstance(state.get("seq"), int) else None
