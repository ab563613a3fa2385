"""A node's process forked in its cgroup (clone3), or moved there after its fork where clone3 cannot: in it either
way before its program runs. The forks happen in a process of one thread, as in the supervisor: this test process
has several, where clone3 refuses to fork."""

import os
import subprocess
import sys
import textwrap
import threading

import pytest

from joshua_codegen.supervisor.cgroup_fork import fork_into_cgroup
from joshua_codegen.supervisor.containment import create_cgroup, own_cgroup, remove_cgroup

pytestmark = pytest.mark.process

# Run in a new interpreter of one thread: the cgroup line of a node's process started by its NodeCgroup (after a
# kill of the cgroup when asked), read by the program the child runs.
NODE_START = """
import os, sys
from joshua_codegen.supervisor.children import child_exec
from joshua_codegen.supervisor.node_processes import NodeCgroup

cgroup, made_in, killed_first = sys.argv[1], sys.argv[2] == "made in", sys.argv[3] == "killed first"
node = NodeCgroup(cgroup, made_in)
if killed_first:
    node.kill()
read_end, write_end = os.pipe()
pid = node.fork()
if pid == 0:
    program = "import sys; sys.stdout.write(open('/proc/self/cgroup').read())"
    child_exec([sys.executable, "-S", "-c", program], dict(os.environ), os.getppid(), node.join, write_end)
os.close(write_end)
with os.fdopen(read_end) as output:
    text = output.read()
_, status = os.waitpid(pid, 0)
print(os.waitstatus_to_exitcode(status), next((line for line in text.splitlines() if line.startswith("0::")), ""))
"""

# Run in a new interpreter: whether clone3 counts as usable for a supervisor whose own cgroup was killed before.
KILLED_SUPERVISOR = """
import os, sys
from joshua_codegen.supervisor.containment import cgroup_usable, join_cgroup, kill_cgroup

killed, fresh = sys.argv[1], sys.argv[2]
kill_cgroup(killed)
join_cgroup(killed)
print(cgroup_usable(fresh, made_in=True))
"""


@pytest.fixture
def cgroup():
    path = create_cgroup(f"joshua-test-{os.getpid()}-{threading.get_ident()}")
    try:
        yield path
    finally:
        remove_cgroup(path)


def run(script: str, *args: str) -> str:
    result = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script), *args], capture_output=True, text=True, timeout=60, check=False
    )
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


@pytest.mark.parametrize("killed_first", ["", "killed first"])
@pytest.mark.parametrize("made_in", ["made in", "moved"])
def test_a_nodes_process_is_in_its_cgroup_when_its_program_runs(cgroup, made_in, killed_first):
    """A kill of the cgroup makes the kernel kill a child forked into it later: the node's processes then join it."""
    line = f"0::{own_cgroup().rstrip('/')}/{os.path.basename(cgroup)}"
    assert run(NODE_START, cgroup, made_in, killed_first) == f"0 {line}"


def test_clone3_counts_as_unusable_where_the_supervisors_own_cgroup_was_killed(cgroup):
    killed, fresh = os.path.join(cgroup, "killed"), os.path.join(cgroup, "fresh")
    os.mkdir(killed)
    os.mkdir(fresh)
    assert run(KILLED_SUPERVISOR, killed, fresh) == "False"


def test_a_directory_that_is_no_cgroup_is_refused(tmp_path):
    script = """
    import sys
    from joshua_codegen.supervisor.cgroup_fork import fork_into_cgroup
    try:
        fork_into_cgroup(sys.argv[1])
    except OSError as exc:
        print(exc)
    """
    assert f"clone3 into {tmp_path}: " in run(script, str(tmp_path))


def test_a_process_of_several_threads_is_refused_with_no_child_made(cgroup):
    pause = threading.Event()
    thread = threading.Thread(target=pause.wait)
    thread.start()
    try:
        with pytest.raises(OSError, match="single-threaded"):
            fork_into_cgroup(cgroup)
    finally:
        pause.set()
        thread.join()
    assert open(os.path.join(cgroup, "cgroup.procs")).read() == ""
