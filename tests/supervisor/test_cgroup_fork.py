"""A node's process forked in its cgroup (clone3), or moved there after its fork where clone3 cannot: in it either
way before its program runs."""

import os
import sys

import pytest

from joshua_codegen.supervisor.cgroup_fork import fork_into_cgroup
from joshua_codegen.supervisor.children import child_exec
from joshua_codegen.supervisor.containment import (
    cgroup_made_in,
    create_cgroup,
    join_cgroup,
    kill_cgroup,
    own_cgroup,
    remove_cgroup,
)
from joshua_codegen.supervisor.node_processes import NodeCgroup

pytestmark = pytest.mark.process

PRINT_CGROUP = "import sys; sys.stdout.write(open('/proc/self/cgroup').read())"


@pytest.fixture
def cgroup():
    path = create_cgroup(f"joshua-test-{os.getpid()}")
    try:
        yield path
    finally:
        remove_cgroup(path)


def cgroup_line_of(fork, join) -> str:
    """The cgroup of a child forked by `fork()` that joins `join` (if any) and then runs Python to print it."""
    read_end, write_end = os.pipe()
    pid = fork()
    if pid == 0:
        child_exec([sys.executable, "-S", "-c", PRINT_CGROUP], dict(os.environ), os.getppid(), join, write_end)
    os.close(write_end)
    with os.fdopen(read_end) as output:
        text = output.read()
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, text
    return next(line for line in text.splitlines() if line.startswith("0::"))


@pytest.mark.parametrize("made_in", [True, False], ids=["forked in it", "moved after the fork"])
def test_a_nodes_process_is_in_its_cgroup_when_its_program_runs(cgroup, made_in):
    node = NodeCgroup(cgroup, made_in)
    assert cgroup_line_of(node.fork, node.join) == f"0::{own_cgroup().rstrip('/')}/{os.path.basename(cgroup)}"


def test_a_directory_that_is_no_cgroup_is_refused_with_no_child_made(tmp_path):
    with pytest.raises(OSError, match="clone3 into"):
        fork_into_cgroup(str(tmp_path))


def test_a_node_killed_through_its_cgroup_starts_again_in_it(cgroup):
    """The kernel kills a child forked into a cgroup that was killed since it was made: after a kill, the node's
    processes join it after their fork."""
    node = NodeCgroup(cgroup, made_in=True)
    node.kill()
    assert cgroup_line_of(node.fork, node.join).endswith(os.path.basename(cgroup))


def test_clone3_counts_as_unusable_where_the_supervisors_own_cgroup_was_killed(cgroup):
    killed, fresh = os.path.join(cgroup, "killed"), os.path.join(cgroup, "fresh")
    os.mkdir(killed)
    os.mkdir(fresh)
    kill_cgroup(killed)
    pid = os.fork()
    if pid == 0:  # a supervisor in a cgroup that was killed before
        code = 2
        try:
            join_cgroup(killed)
            code = 0 if cgroup_made_in(cgroup) is False and cgroup_made_in(fresh) is False else 1
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
