"""The control socket is its owner's alone: a directory or socket another user prepared is refused by the
supervisor (which then does not start) and by `ctl`, and a client of another user is refused by the supervisor.

"Another user" is a real other uid (nobody, testsupport/other_user.py), acting in a sticky, world-writable
directory that stands for /tmp."""

import os
import re
import signal

import pytest
from control_harness import RawClient, ctl, start_robot, status
from supervisor_harness import (
    WAIT_S,
    Supervisor,
    build,
    children_of,
    command_line,
    custom_node,
    events,
    robot,
    wait_started,
)

from joshua_codegen.supervisor.policy import EXIT_PREFLIGHT
from testsupport.other_user import OTHER_UID, as_other_user


@pytest.fixture
def shared(tmp_path):
    """A directory anyone may create entries in, with the sticky bit, like /tmp."""
    directory = tmp_path / "tmp"
    directory.mkdir()
    directory.chmod(0o1777)
    return directory


def test_a_socket_another_user_bound_first_is_refused_by_the_supervisor_and_by_ctl(tmp_path, shared):
    sock = shared / f"joshua-{os.getuid()}" / "r.sock"
    other = as_other_user(shared, "prebind", str(sock.relative_to(shared)))
    try:
        assert other.stdout.readline() == "ready\n"
        assert sock.exists() and sock.parent.stat().st_uid == OTHER_UID
        log = tmp_path / "events.log"
        out = build(tmp_path, robot([custom_node("steady", log)]))
        supervisor = Supervisor(out, "--control-socket", str(sock))
        try:
            code = supervisor.wait()
        finally:
            supervisor.close()
        assert code == EXIT_PREFLIGHT
        refusal = [line for line in supervisor.log().splitlines() if "control socket" in line]
        assert refusal == [
            f"[{refusal[0][1:10]}] supervisor: cannot serve the control socket {sock}: its directory "
            f"{sock.parent} belongs to uid {OTHER_UID}, not to uid {os.getuid()}; remove it, or choose "
            "another path with --control-socket PATH (--no-control for none)"
        ]
        assert events(log) == []  # nothing was started

        answered = ctl(out, sock, "status")
        assert answered.returncode == 3 and answered.stdout == ""  # no supervisor of this user to talk to
        assert answered.stderr == (
            f"supervisor.py ctl: error: control socket {sock} is served by uid {OTHER_UID}, not by uid "
            f"{os.getuid()} or root: not talking to it\n"
        )
    finally:
        other.kill()
        heard = other.communicate()[0]
    assert "status" not in heard  # the other user never saw the request


@pytest.mark.parametrize("owner", ["other user", "own, mode 0777"])
def test_a_directory_others_can_write_in_is_refused(tmp_path, shared, owner):
    sock = shared / f"joshua-{os.getuid()}" / "r.sock"
    if owner == "other user":
        other = as_other_user(shared, "dir777", str(sock.relative_to(shared)))
        assert other.communicate(timeout=WAIT_S)[0] == "" and other.returncode == 0
        reason = f"belongs to uid {OTHER_UID}, not to uid {os.getuid()}"
    else:
        sock.parent.mkdir()
        sock.parent.chmod(0o777)
        reason = "has mode 0777: others may rename or replace the socket in it (it must be 0700)"
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("steady", log)]))
    supervisor = Supervisor(out, "--control-socket", str(sock))
    try:
        code = supervisor.wait()
    finally:
        supervisor.close()
    assert code == EXIT_PREFLIGHT
    assert f"supervisor: cannot serve the control socket {sock}: its directory {sock.parent} {reason};" in (
        supervisor.log()
    )
    assert events(log) == [] and not sock.exists()


def test_the_supervisor_answers_a_client_of_another_user_with_a_refusal(tmp_path):
    out, sock, _, _, supervisor = start_robot(tmp_path)
    try:
        # Even when the owner opens the modes, the other user's connection is refused by its credentials.
        sock.parent.chmod(0o711)
        sock.chmod(0o666)
        other = as_other_user(sock.parent, "client", sock.name)
        heard, complaints = other.communicate(timeout=WAIT_S)
        assert len(heard.splitlines()) == 2, complaints
        reply, after = heard.splitlines()
        assert reply == (
            f'{{"ok": false, "kind": "forbidden", "error": "uid {OTHER_UID} may not use this control socket (only uid {os.getuid()} '
            'and root)"}'
        )
        assert after == "EOF"
        supervisor.wait_log(rf"supervisor: control socket: refused a client of uid {OTHER_UID} \(pid \d+\)")
        assert status(out, sock)["steady"]["state"] == "running"
        own = RawClient(sock)  # the owner is still served
        assert own.request(b'{"command": "status"}\n')["ok"] is True
        own.close()
    finally:
        supervisor.signal()
        code = supervisor.wait()
    assert code == 0


def test_a_socket_of_another_running_supervisor_is_not_taken_over(tmp_path):
    out, sock, _, _, first = start_robot(tmp_path)
    try:
        other_out = build(tmp_path / "second", robot([custom_node("steady", tmp_path / "second.log")]))
        second = Supervisor(other_out, "--control-socket", str(sock))
        try:
            code = second.wait()
        finally:
            second.close()
        assert code == EXIT_PREFLIGHT
        assert (
            f"supervisor: cannot serve the control socket {sock}: another supervisor (pid {first.pid}) serves it; "
            "stop it, or choose another path with --control-socket PATH (--no-control for none)"
        ) in second.log()
        assert not (tmp_path / "second.log").exists()  # nothing was started
        assert status(out, sock)["steady"]["pid"]  # the first supervisor still serves its socket
    finally:
        first.signal()
        assert first.wait() == 0


def test_a_killed_supervisors_socket_is_free_at_once_while_its_guard_still_cleans_up(tmp_path):
    """The guard, forked from the supervisor, ends what it left behind; it holds none of its sockets meanwhile."""
    out, sock, _, log, first = start_robot(tmp_path)
    guard = next(pid for pid in children_of(first.pid) if str(out / "supervisor.py") in command_line(pid))
    os.kill(guard, signal.SIGSTOP)  # as a guard still busy killing the nodes of a large robot
    try:
        first.signal(signal.SIGKILL)
        first.wait()
        second = Supervisor(out, "--control-socket", str(sock))
        try:
            second.wait_log(r"started: 1 of 1 nodes running")
            wait_started(log, "steady", int(re.search(r"steady: started pid (\d+)", second.log()).group(1)))
        finally:
            second.signal()
            code = second.wait()
    finally:
        os.kill(guard, signal.SIGCONT)
    assert code == 0, second.log()


# A sitecustomize for a supervisor: os.closerange, the first thing its guard does after its fork (closing what it
# inherited), waits until the file RELEASE exists; as a guard the kernel has not run yet on a busy machine, it holds
# every descriptor of the supervisor meanwhile, the control socket's listener included.
UNSCHEDULED_GUARD_HOOK = """
import os, time

closerange = os.closerange


def closerange_once_released(*args):
    deadline = time.monotonic() + {wait_s}
    while not os.path.exists({release!r}) and time.monotonic() < deadline:
        time.sleep(0.01)
    closerange(*args)


os.closerange = closerange_once_released
"""


def socket_inodes(pid: int) -> set[str]:
    found = set()
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            target = os.readlink(f"/proc/{pid}/fd/{fd}")
        except OSError:
            continue
        if target.startswith("socket:"):
            found.add(target)
    return found


def test_a_socket_only_a_killed_supervisors_fresh_fork_still_holds_is_taken_over(tmp_path):
    """A killed supervisor's guard that has not run yet holds the listener, and a connection to it succeeds; but
    the supervisor that listened is gone and nothing will ever answer: the path is taken over, not refused."""
    hooks, release = tmp_path / "hooks", tmp_path / "release"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(UNSCHEDULED_GUARD_HOOK.format(wait_s=WAIT_S * 3, release=str(release)))
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("steady", log)]))
    sock = tmp_path / "run" / "r.sock"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(hooks), os.environ.get("PYTHONPATH")])))
    first = Supervisor(out, "--control-socket", str(sock), env=env)
    try:
        first.wait_log(r"started: 1 of 1 nodes running")
        guard = next(pid for pid in children_of(first.pid) if str(out / "supervisor.py") in command_line(pid))
        os.kill(guard, signal.SIGSTOP)
        assert socket_inodes(first.pid) & socket_inodes(guard)  # it has not closed what it inherited yet
        first.signal(signal.SIGKILL)
        first.wait()
        second = Supervisor(out, "--control-socket", str(sock))
        try:
            second.wait_log(r"started: 1 of 1 nodes running|cannot serve")
            assert "cannot serve" not in second.log(), second.log()
            assert status(out, sock)["steady"]["pid"] == int(
                re.search(r"steady: started pid (\d+)", second.log()).group(1)
            )
        finally:
            second.signal()
            code = second.wait()
    finally:
        release.touch()
        os.kill(guard, signal.SIGCONT)
        first.close()
    assert code == 0, second.log()


def test_a_socket_left_by_a_killed_supervisor_is_replaced_and_any_other_file_is_kept(tmp_path):
    out, sock, _, _, first = start_robot(tmp_path)
    first.signal(signal.SIGKILL)
    first.wait()
    assert sock.exists()  # nobody listens on it any more
    second = Supervisor(out, "--control-socket", str(sock))
    try:
        second.wait_log(r"started: 1 of 1 nodes running")
        assert status(out, sock)["steady"]["state"] == "running"
    finally:
        second.signal()
        assert second.wait() == 0
    sock.write_text("a file of the user's\n")
    third = Supervisor(out, "--control-socket", str(sock))
    try:
        assert third.wait() == EXIT_PREFLIGHT
    finally:
        third.close()
    assert f"{sock} exists and is not a socket; remove it, or choose another path" in third.log()
    assert sock.read_text() == "a file of the user's\n"
