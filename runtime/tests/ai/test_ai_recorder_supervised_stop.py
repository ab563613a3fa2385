"""The recorder stopped by its supervisor before its dataset writer has loaded LeRobot: the frames recorded meanwhile
are saved and the robot's stop ends cleanly (exit code 0), however long loading LeRobot takes past the SIGINT grace.

A robot stopped a few seconds after its start on a busy machine does that: the recorder is ready and records at
once, while its writer process still imports LeRobot (seconds of CPU). Saving waits for the import; the recorder
asks the supervisor for more time meanwhile (EXTEND_TIMEOUT_USEC), so no SIGTERM cuts the save short.
"""

import re
import signal
import subprocess
import sys
import time

from ai_support import compiled, mock_camera, mock_encoder, node_block, slow_lerobot_env
from test_ai_recorder import load

from testsupport.joshuac_cli import joshuac

SIGINT_GRACE_S = 2.0  # the description's; loading LeRobot is made to take longer
SLOW_LEROBOT_S = 8.0  # how long any import of lerobot sleeps first in the processes of this robot
STARTUP_TIMEOUT_S = 60.0  # only ends a wait for a robot that never records
STOP_TIMEOUT_S = SLOW_LEROBOT_S + 60.0  # only ends a wait for a stop that never ends
POLL_S = 0.05


def description(output) -> str:
    nodes = [
        mock_camera("camera", "/rec/camera/image_raw", 32, 24, 30.0),
        mock_encoder("leader", "/rec/leader/joint_states", ["shoulder_pan", "gripper"], 30.0),
        mock_encoder("follower", "/rec/follower/joint_states", ["shoulder_pan", "gripper"], 30.0),
        node_block(
            "recorder",
            "DATA_SUBSCRIBER",
            topic_name="/rec/leader/joint_states",
            input_topics=["/rec/camera/image_raw", "/rec/follower/joint_states"],
            output_directory=str(output),
            output_format="parquet",
            rate_hz=10.0,
        ),
    ]
    compiled("MODE_DATA_COLLECTION", *nodes)  # fails the test with joshuac's diagnostics if it does not compile
    return (
        f'robot_config {{\n  name: "recording_arm"\n  mode: MODE_DATA_COLLECTION\n'
        f"  shutdown {{ sigint_grace_s: {SIGINT_GRACE_S} }}\n{''.join(nodes)}}}\n"
    )


def wait_for(log_path, pattern: str, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if re.search(pattern, log_path.read_text(), re.M):
            return
        time.sleep(POLL_S)
    raise AssertionError(f"no {pattern!r} in the supervisor's log:\n{log_path.read_text()}")


def test_a_robot_stopped_while_the_recorder_still_loads_lerobot_saves_its_frames_and_exits_0(
    tmp_path, ai_env, lerobot_offline
):
    output = tmp_path / "dataset"
    (tmp_path / "robot.pbtxt").write_text(description(output))
    built = joshuac("build", tmp_path / "robot.pbtxt", "-o", tmp_path / "out")
    assert built.returncode == 0, built.stderr
    env = slow_lerobot_env(tmp_path, ai_env, SLOW_LEROBOT_S)
    log_path = tmp_path / "supervisor.log"
    with open(log_path, "w") as log:
        supervisor = subprocess.Popen(
            [sys.executable, str(tmp_path / "out" / "supervisor.py"), "--no-control"],
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    try:
        wait_for(log_path, r"recorder\]: first frame of the episode recorded", STARTUP_TIMEOUT_S)
        assert "dataset writer ready" not in log_path.read_text()  # LeRobot is still loading
        supervisor.send_signal(signal.SIGINT)
        code = supervisor.wait(STOP_TIMEOUT_S)
    finally:
        if supervisor.poll() is None:
            supervisor.kill()
            supervisor.wait()
    text = log_path.read_text()
    assert code == 0, text
    assert "escalating" not in text
    assert re.search(r"recorder: stopping takes longer: it asks for [\d.]+ s more \(saving \d+ frames: ", text), text
    frames = int(re.search(r"episode 0 saved: (\d+) frames", text).group(1))
    assert len(load(output)) == frames > 0
