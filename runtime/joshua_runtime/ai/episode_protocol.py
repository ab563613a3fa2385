"""How a recorder is told what to do with its episodes, how it answers, and how it reports its progress.

Three std_msgs/String topics. Commands go to `/<recorder>/episode`:
- `start [task]`: record an episode (task text: the one given, else the robot name); during a reset
  period, it ends the reset at once.
- `stop`: save the episode in progress and record nothing more; during a reset period, end it.
- `discard`: drop the episode in progress.
- `next`: save the episode in progress, then, after the reset period (reset_time_s), record the next
  one with the same task; during a reset period, start that next episode now (lerobot-record's right
  arrow). An episode that has lasted episode_time_s ends this way by itself.
- `rerecord`: drop the episode in progress and, after the reset period, record it again; with none in
  progress, remove the episode this recorder saved last from the dataset and record it again at once
  (lerobot-record's left arrow).

The recorder answers on
`/<recorder>/episode_state` with one JSON object per event, e.g.
`{"seq": 4, "event": "saved", "recording": false, "episode": 3, "frames": 412, "episodes": 4,
"message": "saved episode 3 (412 frames) in /data/pick"}`. `seq` counts the recorder's events; the
topic keeps the last EVENTS_KEPT for late subscribers (TRANSIENT_LOCAL), so a client learns the current
state as soon as it connects and no answer is replaced by the next event, then waits for an event with a higher `seq` that answers its command.

Events: `ready` (the recorder is ready and recording its first episode), `started`, `saved`, `empty`
(an episode without frames: nothing saved), `discarded`, `stopped` (a reset period ended by `stop`),
`rerecording` (the episode in progress was dropped to be recorded again), `removed` (the last saved
episode was removed to be recorded again), `ignored` (a command that did not apply, e.g. `stop` with no
episode recording), `failed` (the episode could not be saved).

Progress goes to `/<recorder>/episode_progress`, the last one kept for late subscribers, every
PROGRESS_PERIOD_S, after each event and at each change: `{"phase": "recording" | "resetting" | "idle", "task",
"episodes" (saved in the dataset: also the index the episode in progress will have),
"elapsed_s" (of the episode or reset period), "remaining_s" (until episode_time_s or the end of the
reset; null when unlimited), "frames", "skipped", "writer": "loading" | "ready", "seq" (of the last
event)}`. A client that joins waits until the kept events reached it up to that `seq`: an event from
before it came must not pass for the answer to its command.
"""

import json

COMMAND_TOPIC = "~/episode"
STATE_TOPIC = "~/episode_state"
PROGRESS_TOPIC = "~/episode_progress"
PROGRESS_PERIOD_S = 0.5
COMMAND_QOS_DEPTH = 10
EVENTS_KEPT = 32
COMMANDS = ("start", "stop", "discard", "next", "rerecord")
PHASES = ("recording", "resetting", "idle")
# The events that answer each command (the first ones are success).
ANSWERS = {
    "start": ("started", "ignored"),
    "stop": ("saved", "empty", "stopped", "ignored", "failed"),
    "discard": ("discarded", "ignored", "failed"),
    "next": ("saved", "empty", "started", "ignored", "failed"),
    "rerecord": ("rerecording", "removed", "ignored", "failed"),
}
SUCCESS = ("started", "saved", "empty", "discarded", "stopped", "rerecording", "removed")


def state_qos(depth: int = EVENTS_KEPT):
    """The state topic's QoS: reliable, its last `depth` events kept for subscribers that join later and for
    bursts (a command's answer and the writer's answer to the one before leave within milliseconds; with one
    kept, the second replaces the first before a busy client has it). The progress topic keeps one."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )


def progress_qos():
    """The progress topic's QoS: as the state topic's, only the latest progress kept."""
    return state_qos(depth=1)


def topic(node_name: str, relative: str) -> str:
    """The absolute name of one of a recorder's topics: topic("rec", STATE_TOPIC) -> /rec/episode_state."""
    return f"/{node_name}/{relative.removeprefix('~/')}"


def encode(state: dict) -> str:
    return json.dumps(state, sort_keys=True)


def decode(text: str) -> dict | None:
    """The state object of a message, or None when it is not one."""
    try:
        state = json.loads(text)
    except ValueError:
        return None
    return state if isinstance(state, dict) and isinstance(state.get("seq"), int) else None


def decode_progress(text: str) -> dict | None:
    """The progress object of a message, or None when it is not one."""
    try:
        progress = json.loads(text)
    except ValueError:
        return None
    return progress if isinstance(progress, dict) and progress.get("phase") in PHASES else None
