"""The node starter's process on its own, driven by a small stand-in supervisor (a child subreaper): what a node it
forks gets (arguments, command line, environment, session, signals, output, exit code) and how it answers."""

import json
import subprocess
import sys

PROBE = """
import json, os, signal, sys
with open("/proc/self/cmdline", "rb") as file:
    cmdline = file.read().rstrip(b"\\0").split(b"\\0")
print(json.dumps({
    "argv": sys.argv, "path0": sys.path[0], "name": __name__, "cmdline": [part.decode() for part in cmdline],
    "environment": dict(os.environ), "parent": os.getppid(), "session": os.getsid(0), "pid": os.getpid(),
    "sigint": signal.getsignal(signal.SIGINT) is signal.default_int_handler,
    "sigpipe": signal.getsignal(signal.SIGPIPE) == signal.SIG_IGN,
    "sigterm": signal.getsignal(signal.SIGTERM) == signal.SIG_DFL,
    "blocked": sorted(int(number) for number in signal.pthread_sigmask(signal.SIG_BLOCK, [])),
}), flush=True)
sys.exit(int(os.environ.get("PROBE_EXIT", "0")))
"""

# The stand-in supervisor: starts the starter on a socket pair, asks for the entrypoints in argv at once (each with
# the environment PROBE_EXIT=<its index>), and prints, per node, its pid, exit status and output as JSON.
SUPERVISOR = r"""
import array, ctypes, json, os, socket, subprocess, sys, time
ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER
ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
code = "import sys; del sys.path[0]; from joshua_runtime.node_starter.server import main; sys.exit(main(sys.argv[1:]))"
starter = subprocess.Popen([sys.executable, "-c", code, "--socket-fd", str(theirs.fileno())] + [""] * 300,
                           pass_fds=[theirs.fileno()])
theirs.close()
assert ours.recv(100) == b"ready"
pipes = []
for number, entrypoint in enumerate(sys.argv[1:]):
    read_end, write_end = os.pipe()
    fields = [str(number), entrypoint, "", str(os.getpid()), f"PROBE_EXIT={number}", "ONLY=this"]
    ours.sendmsg([b"\0".join(field.encode() for field in fields)],
                 [(socket.SOL_SOCKET, socket.SCM_RIGHTS, array.array("i", [write_end]))])
    os.close(write_end)
    pipes.append(read_end)
replies = sorted(ours.recv(100).decode().split() for _ in sys.argv[1:])
ours.sendmsg([b"not a request"])
invalid = ours.recv(100).decode()
results = []
for (kind, number, pid), read_end in zip(replies, pipes):
    deadline = time.monotonic() + 30
    while True:  # the node is this process's child once its go-between has exited
        try:
            _, status = os.waitpid(int(pid), 0)
            break
        except ChildProcessError:
            assert time.monotonic() < deadline
            time.sleep(0.001)
    with os.fdopen(read_end) as output:
        results.append({"kind": kind, "pid": int(pid), "status": os.waitstatus_to_exitcode(status), "output": output.read()})
ours.close()
print(json.dumps({"results": results, "invalid": invalid, "starter": starter.wait(30), "supervisor": os.getpid()}))
"""


def run_starter(tmp_path, *entrypoints) -> dict:
    script = tmp_path / "supervisor.py"
    script.write_text(SUPERVISOR)
    done = subprocess.run(
        [sys.executable, str(script), *map(str, entrypoints)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_a_forked_node_runs_its_entrypoint_as_an_exec_d_interpreter_would(tmp_path):
    entrypoint = tmp_path / "nodes" / "probe.py"
    entrypoint.parent.mkdir()
    entrypoint.write_text(PROBE)
    report = run_starter(tmp_path, entrypoint, entrypoint, entrypoint)
    assert [result["status"] for result in report["results"]] == [0, 1, 2]  # each its own PROBE_EXIT
    for result in report["results"]:
        seen = json.loads(result["output"])
        assert seen["pid"] == result["pid"] and seen["parent"] == report["supervisor"]
        assert seen["argv"] == [str(entrypoint)] and seen["name"] == "__main__"
        assert seen["path0"] == str(entrypoint.parent)
        assert seen["cmdline"] == [sys.executable, str(entrypoint)]
        assert seen["environment"] == {"PROBE_EXIT": seen["environment"]["PROBE_EXIT"], "ONLY": "this"}
        assert seen["session"] == seen["pid"]
        assert seen["sigint"] and seen["sigpipe"] and seen["sigterm"] and seen["blocked"] == []
    assert report["invalid"].startswith("invalid request: ")
    assert report["starter"] == 0  # it ended when its socket closed


def test_an_uncaught_exception_ends_the_node_with_its_traceback_and_1(tmp_path):
    entrypoint = tmp_path / "broken.py"
    entrypoint.write_text("raise RuntimeError('the node broke')\n")
    [result] = run_starter(tmp_path, entrypoint)["results"]
    assert result["status"] == 1
    assert "Traceback" in result["output"] and "RuntimeError: the node broke" in result["output"]


def test_lttng_fork_handlers_are_found_wherever_rclpy_loads_lttng():
    code = (
        "import rclpy\n"
        "from joshua_runtime.node_starter.fork_hooks import loaded_libraries, lttng_fork_hooks\n"
        "print(any('liblttng-ust' in path for path in loaded_libraries()), lttng_fork_hooks() is not None)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    loaded, found = done.stdout.split()
    assert found == loaded, done.stderr
