"""A node's overlong output lines reach its log file, `ctl logs` and the supervisor's stderr cut and marked."""

from supervisor_harness import PYTHON, Supervisor, build, ctl, custom_node, quoted, robot, unstamped, wait_until

from joshua_codegen.supervisor.node_log import LINE_CUT_MARK, LINE_MAX_BYTES

PIECES = 3  # the flood is PIECES lines of LINE_MAX_BYTES, cut, then a short rest
# A node writing PIECES x LINE_MAX_BYTES + 10 bytes without a newline in small writes, then "end".
FLOOD = (
    "import os, sys, time\n"
    f"for _ in range({PIECES * LINE_MAX_BYTES + 10} // 1000):\n"
    "    os.write(1, b'x' * 1000)\n"
    f"os.write(1, b'x' * ({PIECES * LINE_MAX_BYTES + 10} % 1000) + b'\\nend\\n')\n"
    "time.sleep(3600)\n"
)


def test_an_overlong_line_is_cut_and_marked_in_the_log_file_ctl_logs_and_stderr(tmp_path):
    flood = f'node {{ name: "flood" type: CUSTOM executable: "{PYTHON}" args: ["-c", {quoted(FLOOD)}] }}'
    out = build(tmp_path, robot([custom_node("steady", tmp_path / "events.log"), flood]))
    sock, logs = tmp_path / "r.sock", tmp_path / "logs"
    supervisor = Supervisor(out, "--control-socket", str(sock), "--log-dir", str(logs))
    mark = LINE_CUT_MARK.decode()
    expected = ["x" * LINE_MAX_BYTES + mark] * PIECES + ["x" * 10, "end"]
    try:
        written = logs / "flood.log"
        wait_until(lambda: written.exists() and written.read_text().endswith("end\n"), "the flood's end")
        header, *lines = [unstamped(line) for line in written.read_text().splitlines()]
        assert header.startswith("-- run ") and lines == expected
        shown = ctl(out, sock, "logs", "flood", "-n", str(len(expected)))
        assert [unstamped(line) for line in shown.stdout.splitlines()] == expected
        supervisor.wait_log(r"^end$")
        assert supervisor.log().count(mark + "\n") == PIECES
    finally:
        supervisor.signal()
        supervisor.wait()
