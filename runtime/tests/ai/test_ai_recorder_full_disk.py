"""The recorder on a disk that fills up mid-episode: it stops at the failed write and exits 6 by itself.

The output directory is a 2 MiB tmpfs mounted for the test; one episode is saved, the next one starts,
then the test fills the filesystem and sends nothing more. The node must notice the first write that
fails (a PNG of the image writer, or the video encoder's file), end the episode as lost, say so in one
line and exit 6, without waiting for a stop command; the episode saved before stays loadable.
"""

import pytest
from ai_support import RELIABLE, NodeProcess
from std_msgs.msg import String
from test_ai_recorder import Sensors, load, record_one, recorder_settings, send

from testsupport.small_filesystem import fill, small_filesystem

EXIT_TIMEOUT_S = 60.0  # only ends a node that never notices; it exits within a frame or two


@pytest.mark.parametrize("output_format", ["parquet", "lerobot"])
def test_a_full_disk_ends_the_episode_at_the_first_failed_write(
    tmp_path, ai_env, ros_peer, lerobot_offline, output_format
):
    with small_filesystem(tmp_path / "small") as small:
        output = small / "dataset"
        Sensors(ros_peer)
        commands = ros_peer.publisher("/ai_recorder/episode", String, RELIABLE)
        node = NodeProcess(recorder_settings(output, output_format), ai_env)
        try:
            record_one(node, 0)
            mark = node.count()
            send(ros_peer, commands, "stop")
            node.wait_for(r"episode 0 saved", after=mark)
            mark = node.count()
            send(ros_peer, commands, "start")
            record_one(node, mark)
            fill(small)
            code = node.process.wait(EXIT_TIMEOUT_S)
            node._reader.join(EXIT_TIMEOUT_S)
        finally:
            node.kill()
        assert code == 6, node.output
        errors = [line for line in node.lines if line.startswith("ai_recorder: error")]
        assert len(errors) == 1, node.output
        assert errors[0].startswith("ai_recorder: error: episode of ")
        assert f"frames lost, not saved to {output}: " in errors[0]
        assert f"[Errno 28] No space left on device: '{output}.staging/" in errors[0]  # the file that failed
        after = node.lines[node.lines.index(errors[0]) :]
        assert not [line for line in after if "episode stopped" in line], node.output  # lost, not saved
        assert not [line for line in node.lines if "Error writing image" in line], node.output
        (small / "filler").unlink()
        dataset = load(output)
        assert dataset.meta.total_episodes == 1 and len(dataset) > 0
