"""The episode workflow lerobot-record users know, on a real recorder: next, reset periods, re-record, status.

`joshua-episode` sends the commands and reads the progress reports; the saved dataset is read back
with LeRobotDataset to check which episodes it holds and that each holds the values of its phase.
"""

import json
import re
import signal
import subprocess
import sys
from pathlib import Path

from ai_support import NodeProcess, compiled, mock_camera, mock_encoder, node_block
from test_ai_recorder import HEIGHT, JOINTS, PUBLISH_HZ, RATE_HZ, WIDTH, Sensors, load

EPISODE = str(Path(sys.executable).parent / "joshua-episode")
RECORDER = "ai_recorder"
CLI_TIMEOUT_S = 120
LONG_RESET_S = 600.0  # a reset only a command ends
FIRST_FRAME = "first frame of the episode recorded"


def settings(output: Path, **fields) -> dict:
    return compiled(
        "MODE_DATA_COLLECTION",
        mock_camera("camera", "/rec/camera/image_raw", WIDTH, HEIGHT, PUBLISH_HZ),
        mock_encoder("leader", "/rec/leader/joint_states", JOINTS, PUBLISH_HZ),
        mock_encoder("follower", "/rec/follower/joint_states", JOINTS, PUBLISH_HZ),
        node_block(
            RECORDER,
            "DATA_SUBSCRIBER",
            topic_name="/rec/leader/joint_states",
            input_topics=["/rec/camera/image_raw", "/rec/follower/joint_states"],
            output_directory=str(output),
            output_format="parquet",
            rate_hz=RATE_HZ,
            **fields,
        ),
    )[RECORDER]


def episode(env: dict, *arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [EPISODE, *arguments, "--node", RECORDER], env=env, capture_output=True, text=True, timeout=CLI_TIMEOUT_S
    )


def answered(env: dict, command: str, pattern: str) -> re.Match:
    result = episode(env, command)
    assert result.returncode == 0, result.stderr
    found = re.fullmatch(f"{RECORDER}: {pattern}\n", result.stdout)
    assert found, result.stdout
    return found


def phases_of(dataset, episode_index: int, sensors) -> set[int]:
    """The phases whose action values the frames of one episode hold."""
    start = dataset.meta.episodes[episode_index]["dataset_from_index"]
    stop = dataset.meta.episodes[episode_index]["dataset_to_index"]
    return {int(round(float(dataset[i]["action"][0]))) for i in range(start, stop)}


def test_next_reset_rerecord_and_status(tmp_path, ai_env, ros_peer, lerobot_offline):
    output = tmp_path / "dataset"
    sensors = Sensors(ros_peer)
    node = NodeProcess(settings(output, reset_time_s=LONG_RESET_S), ai_env)
    try:
        node.wait_for(FIRST_FRAME)
        status = episode(ai_env, "status")
        assert status.returncode == 0, status.stderr
        assert re.fullmatch(
            rf"{RECORDER}: recording episode 0 \(task: test_arm\): [\d.]+ s, \d+ frames( \(\d+ skipped\))?; "
            r"0 episodes saved(; dataset writer loading LeRobot)?\n",
            status.stdout,
        ), status.stdout
        saved = [int(answered(ai_env, "next", rf"saved episode 0 \((\d+) frames\) in {output}").group(1))]
        status = episode(ai_env, "status", "--json")
        progress = json.loads(status.stdout)
        assert progress["phase"] == "resetting" and progress["episodes"] == 1 and progress["frames"] == 0
        assert 0 < progress["remaining_s"] <= LONG_RESET_S

        sensors.set_phase(1)
        mark = node.count()
        answered(ai_env, "next", r"episode started \(task: test_arm\)")  # ends the reset now
        node.wait_for(FIRST_FRAME, after=mark)
        answered(
            ai_env,
            "rerecord",
            rf"dropped the episode in progress \(\d+ frames\); resetting for {LONG_RESET_S:g} s, then recording it again",
        )
        assert '"phase": "resetting"' in episode(ai_env, "status", "--json").stdout

        sensors.set_phase(2)
        mark = node.count()
        answered(ai_env, "start", r"episode started \(task: test_arm\)")
        node.wait_for(FIRST_FRAME, after=mark)
        removed = int(answered(ai_env, "stop", rf"saved episode 1 \((\d+) frames\) in {output}").group(1))

        sensors.set_phase(3)
        mark = node.count()
        answered(ai_env, "rerecord", rf"removed episode 1 \({removed} frames\) from {output}; recording it again")
        node.wait_for(FIRST_FRAME, after=mark)
        saved.append(int(answered(ai_env, "stop", rf"saved episode 1 \((\d+) frames\) in {output}").group(1)))
        idle = episode(ai_env, "stop")
        assert idle.returncode == 1 and "ignored: no episode is recording" in idle.stderr
        assert node.stop(signal.SIGINT) == 0
    finally:
        node.kill()

    dataset = load(output)
    assert dataset.meta.total_episodes == 2 and len(dataset) == sum(saved)
    assert phases_of(dataset, 0, sensors) == {0}
    assert phases_of(dataset, 1, sensors) == {3}  # the re-recorded episode replaced the one of phase 2
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("dataset")) == ["dataset"]


def test_episode_time_and_reset_period_run_the_episodes_by_themselves(tmp_path, ai_env, ros_peer, lerobot_offline):
    episode_time_s, reset_time_s = 1.0, 1.0
    output = tmp_path / "dataset"
    Sensors(ros_peer)
    node = NodeProcess(settings(output, episode_time_s=episode_time_s, reset_time_s=reset_time_s), ai_env)
    try:
        node.wait_for(r"episode 1 saved: (\d+) frames")
        assert node.stop(signal.SIGINT) == 0
    finally:
        node.kill()
    lines = node.lines
    order = [
        next(i for i, line in enumerate(lines) if pattern in line)
        for pattern in ("episode_time_s (1 s) reached", "resetting for 1 s", "reset period over", "episode 0 saved")
    ]
    assert order[:3] == sorted(order[:3]), node.output
    dataset = load(output)
    assert dataset.meta.total_episodes >= 2
    most = round(episode_time_s * RATE_HZ) + 1
    lengths = [dataset.meta.episodes[e]["length"] for e in range(2)]
    assert all(0 < length <= most for length in lengths), lengths
