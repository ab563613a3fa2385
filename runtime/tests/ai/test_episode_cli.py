"""`joshua-episode` against a real recorder process: every command answered with what the recorder did."""

import subprocess
import sys
from pathlib import Path

from ai_support import ROBOT, NodeProcess, compiled, mock_encoder, node_block
from sensor_msgs.msg import JointState

from testsupport.joshuac_cli import joshuac

EPISODE = str(Path(sys.executable).parent / "joshua-episode")
JOINTS = ["shoulder_pan", "gripper"]
RECORDER = "episode_recorder"
CLI_TIMEOUT_S = 120
NO_RECORDER_WAIT_S = 1  # how long the "no recorder" case looks for one (the command's default: 10 s)


def nodes(output: Path) -> str:
    return (
        mock_encoder("leader", "/ep/leader/joint_states", JOINTS, 30.0)
        + mock_encoder("follower", "/ep/follower/joint_states", JOINTS, 30.0)
        + node_block(
            RECORDER,
            "DATA_SUBSCRIBER",
            topic_name="/ep/leader/joint_states",
            input_topics=["/ep/follower/joint_states"],
            output_directory=str(output),
            output_format="parquet",
            rate_hz=10.0,
        )
    )


def episode(env: dict, *arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run([EPISODE, *arguments], env=env, capture_output=True, text=True, timeout=CLI_TIMEOUT_S)


def test_start_stop_and_discard_report_what_the_recorder_did(tmp_path, ai_env, ros_peer, lerobot_offline):
    from joshua_runtime.ai.ros_arrays import joint_state

    settings = compiled("MODE_DATA_COLLECTION", nodes(tmp_path / "dataset"))[RECORDER]
    for arm in ("leader", "follower"):
        ros_peer.publish_periodically(
            f"/ep/{arm}/joint_states", JointState, 30.0, lambda: joint_state(JOINTS, [0.1, 0.2])
        )
    node = NodeProcess(settings, ai_env)
    try:
        node.wait_for(r"ready: recording 2 topics at 10 fps")
        node.wait_for("first frame of the episode recorded")
        stopped = episode(ai_env, "stop", "--node", RECORDER)
        assert stopped.returncode == 0, stopped.stderr
        frames = int(node.wait_for(r"episode 0 saved: (\d+) frames").group(1))
        assert stopped.stdout == f"{RECORDER}: saved episode 0 ({frames} frames) in {tmp_path / 'dataset'}\n"

        again = episode(ai_env, "stop", "--node", RECORDER)
        assert again.returncode == 1
        assert again.stderr == f"joshua-episode: {RECORDER}: episode command 'stop' ignored: no episode is recording\n"

        (tmp_path / "robot.pbtxt").write_text(  # the robot's build names its ROS domain
            f'robot_config {{ name: "{ROBOT}" mode: MODE_DATA_COLLECTION ros_domain_id: {ai_env["ROS_DOMAIN_ID"]}\n'
            + nodes(tmp_path / "dataset")
            + "}\n"
        )
        built = joshuac("build", tmp_path / "robot.pbtxt", "-o", tmp_path / "out")
        assert built.returncode == 0, built.stderr
        without_domain = {key: value for key, value in ai_env.items() if key != "ROS_DOMAIN_ID"}
        mark = node.count()
        started = episode(without_domain, "start", "--task", "pick the cube", "--robot", str(tmp_path / "out"))
        assert (started.returncode, started.stdout) == (0, f"{RECORDER}: episode started (task: pick the cube)\n")
        node.wait_for("first frame of the episode recorded", after=mark)
        discarded = episode(ai_env, "discard", "--node", RECORDER)
        assert discarded.returncode == 0, discarded.stderr
        assert discarded.stdout.startswith(f"{RECORDER}: discarded the episode (")
    finally:
        node.kill()


def test_no_recorder_is_a_clear_error(ai_env):
    missing = episode(ai_env, "stop", "--node", "nobody", "--discovery-timeout", str(NO_RECORDER_WAIT_S))
    assert missing.returncode == 3
    assert missing.stderr.startswith(
        f"joshua-episode: error: no recorder answers on /nobody/episode in ROS domain "
        f"{ai_env['ROS_DOMAIN_ID']} within {NO_RECORDER_WAIT_S} s"
    )


def test_a_robot_without_a_recorder_is_a_usage_error(tmp_path, ai_env):
    (tmp_path / "robot.pbtxt").write_text(
        f'robot_config {{ name: "{ROBOT}" mode: MODE_TELEOPERATION\n'
        + mock_encoder("leader", "/leader/joint_states", JOINTS, 30.0)
        + "}\n"
    )
    assert joshuac("build", tmp_path / "robot.pbtxt", "-o", tmp_path / "out").returncode == 0
    refused = episode(ai_env, "start", "--robot", str(tmp_path / "out"))
    assert refused.returncode == 2
    assert refused.stderr == (
        f"joshua-episode: error: {tmp_path / 'out' / 'manifest.json'}: 0 DATA_SUBSCRIBER nodes "
        "(none); name one with --node\n"
    )
