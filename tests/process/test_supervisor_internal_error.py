"""A bug in the supervisor itself (an exception it did not expect) is logged with its traceback, stops every
node with the normal cascade and ends the supervisor with its own exit code, never with nodes left running."""

import pytest
from control_harness import ctl
from supervisor_harness import Supervisor, alive, build, custom_node, events, robot, wait_until

from joshua_codegen.supervisor.policy import EXIT_INTERNAL, INTERNAL_ERRORS_MAX

# (the line a fault is put after in the generated supervisor_code.py, supervisor arguments, how it is reached)
FAULTS = {
    "timer": ("    def print_status(self, now):\n", ["--status-interval", "0.3"], None),
    "control request": ("    def status(self) -> dict:\n", [], "status"),
}


@pytest.mark.parametrize("where", sorted(FAULTS))
def test_an_unexpected_exception_stops_every_node_with_the_cascade_and_exits_70(tmp_path, where):
    assert EXIT_INTERNAL == 70
    anchor, args, ctl_command = FAULTS[where]
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log), custom_node("b", log, "SIGINT=ignore")]))
    script = out / "supervisor_code.py"  # the code supervisor.py runs: edited, it is compiled from this source
    text = script.read_text()
    assert text.count(anchor) == 1
    # The fault waits for both nodes' handlers: a SIGINT before its handler ends a node without a word.
    trigger = tmp_path / "fail-now"
    fault = f"        if os.path.exists({str(trigger)!r}):\n            raise RuntimeError('injected fault')\n"
    script.write_text(text.replace(anchor, anchor + fault))
    sock = tmp_path / "run" / "r.sock"
    supervisor = Supervisor(out, "--control-socket", str(sock), *args)
    try:
        wait_until(lambda: len(events(log)) >= 2, "both nodes to start")
        trigger.touch()
        if ctl_command:
            ctl(out, sock, ctl_command)
        code = supervisor.wait()
    finally:
        supervisor.close()
    assert code == EXIT_INTERNAL
    text = supervisor.log()
    assert "Traceback (most recent call last):" in text and "RuntimeError: injected fault" in text
    assert "supervisor: internal error (a bug in supervisor.py): stopping every node" in text
    assert sorted((name, note) for name, _, note in events(log) if note != "start") == [
        ("a", "got SIGINT exit"),
        ("b", "got SIGINT ignore"),
        ("b", "got SIGTERM exit"),
    ]
    assert not any(alive(pid) for _, pid, _ in events(log))
    assert not sock.exists()


def test_a_fault_that_keeps_coming_back_ends_with_sigkill_and_no_node_left(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("deaf", log, "SIGINT=ignore", "SIGTERM=ignore")], sigint=30, sigterm=30))
    script = out / "supervisor_code.py"  # the code supervisor.py runs: edited, it is compiled from this source
    anchor = "    def reap(self):\n"  # runs on every turn of the loop, stopping or not
    text = script.read_text()
    assert text.count(anchor) == 1
    trigger = tmp_path / "fail-now"
    fault = f"        if os.path.exists({str(trigger)!r}):\n            raise RuntimeError('injected fault')\n"
    script.write_text(text.replace(anchor, anchor + fault))
    supervisor = Supervisor(out, "--control-socket", str(tmp_path / "run" / "r.sock"), "--status-interval", "0.1")
    try:
        wait_until(lambda: events(log), "the node to start")
        trigger.touch()
        code = supervisor.wait()
    finally:
        supervisor.close()
    assert code == EXIT_INTERNAL
    text = supervisor.log()
    assert text.count("RuntimeError: injected fault") == INTERNAL_ERRORS_MAX
    assert f"supervisor: {INTERNAL_ERRORS_MAX} internal errors: killing every process left (SIGKILL)" in text
    wait_until(lambda: not any(alive(pid) for _, pid, _ in events(log)), "the node to be killed")
