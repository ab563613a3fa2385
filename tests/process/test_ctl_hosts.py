"""`ctl --host` and `ctl status --all-hosts` on a robot of one computer: a usage error, before any socket is touched."""

from supervisor_harness import build, ctl, robot

NODE = 'node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }'


def test_host_options_of_a_robot_on_one_computer_are_usage_errors(tmp_path):
    out = build(tmp_path, robot([NODE]))
    for arguments in (("--host", "arm", "status"), ("status", "--all-hosts"), ("--host", "arm", "restart", "leader")):
        done = ctl(out, tmp_path / "missing.sock", *arguments)
        assert done.returncode == 2, (arguments, done)
        assert "robot r runs on one computer: --host and --all-hosts are for a robot on several" in done.stderr
