"""The recorder's video encoder is quiet in the supervisor's output unless asked for detail.

SVT-AV1 prints its banner and configuration (about 20 `Svt[info]:` lines) and warnings to stderr each
time an episode's encoder starts. The recorder process's whole output (stdout and stderr, as the
supervisor collects it) is captured while it encodes an episode: no `Svt[` line by default, and the
banner again when the documented switch, SVT_LOG=3 in the recorder's environment, asks for it.
"""

import signal

import pytest
from ai_support import NodeProcess
from test_ai_recorder import Sensors, record_one, recorder_settings

VERBOSE_LOG_LEVEL = "3"  # SVT-AV1's info level, the library's own default


def encoder_lines(tmp_path, env) -> tuple[list[str], list[str]]:
    """(every `Svt[` line, every line) of a recorder that encodes one episode and saves it at SIGINT."""
    node = NodeProcess(recorder_settings(tmp_path / "dataset", "lerobot"), env)
    try:
        record_one(node, 0)
        assert node.stop(signal.SIGINT) == 0, node.output
        node.wait_for(r"episode 0 saved: \d+ frames")
    finally:
        node.kill()
    return [line for line in node.lines if line.startswith("Svt[")], node.lines


@pytest.mark.parametrize("verbose", [False, True], ids=["default", "SVT_LOG=3"])
def test_the_encoder_banner_shows_only_when_asked_for(tmp_path, ai_env, ros_peer, lerobot_offline, verbose):
    Sensors(ros_peer)
    env = dict(ai_env)
    env.pop("SVT_LOG", None)
    if verbose:
        env["SVT_LOG"] = VERBOSE_LOG_LEVEL
    banner, lines = encoder_lines(tmp_path, env)
    if verbose:
        assert any(line.startswith("Svt[info]: SVT [version]:") for line in banner), lines
        assert any(line.startswith("Svt[info]: SVT [config]:") for line in banner), lines
    else:
        assert banner == [], lines
