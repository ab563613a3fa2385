"""The MCAP recorder on a disk that fills up: the first failed write ends it with exit 6 and one line.

The output directory is a 2 MiB tmpfs mounted for the test. Once the recorder has written a chunk,
the test fills the filesystem: the node must stop at the write that fails, say so in one line (no
second error from trying to finish the bag on the same full disk) and exit 6 without being asked to
stop, leaving the bag readable up to its last finished chunk.
"""

from bag_support import ARM, two_arm_recorder
from mcap.exceptions import EndOfFile
from mcap.reader import NonSeekingReader
from sensor_msgs.msg import JointState
from test_bag_recorder import RELIABLE, WAIT_S

from testsupport.small_filesystem import fill, small_filesystem

EXIT_TIMEOUT_S = 30.0  # only ends a node that never notices; it exits at its next chunk (1 s)


def messages_readable(path) -> int:
    with open(path, "rb") as stream:
        count = 0
        try:
            for _ in NonSeekingReader(stream).iter_messages(log_time_order=False):
                count += 1
        except EndOfFile:
            pass
        return count


def test_a_full_disk_ends_the_bag_recorder_at_the_first_failed_write(start_node, ros_client, tmp_path):
    with small_filesystem(tmp_path / "small") as small:
        settings = two_arm_recorder(small / "bags")
        ros_client.listen(ARM, JointState, RELIABLE, keep=1000)
        start_node(settings["arm"])
        start_node(settings["follower"])
        recorder = start_node(settings["recorder"])
        assert ros_client.spin_until(lambda: len(ros_client.messages(ARM)) > 20, WAIT_S), recorder.failure()
        # The recorder makes its bag when it starts, which a busy machine may leave until after the arm's messages.
        assert ros_client.spin_until(lambda: any((small / "bags").glob("*/*.mcap")), WAIT_S), recorder.failure()
        [path] = (small / "bags").glob("*/*.mcap")
        bag = path.parent
        assert ros_client.spin_until(lambda: messages_readable(path) > 0, WAIT_S), recorder.failure()
        fill(small)
        code, stderr = recorder.wait(EXIT_TIMEOUT_S)
        assert code == 6, stderr
        errors = [line for line in stderr.splitlines() if "error" in line]
        assert errors == [f"recorder: error: cannot write to the bag {bag}: [Errno 28] No space left on device"]
        assert messages_readable(path) > 0
        assert (bag / "metadata.yaml").is_file()
