"""Whether the nodes' cgroup can hold them, told without forking: the kernel's conditions, checked on real cgroups."""

import os

import pytest

from joshua_codegen.supervisor.containment import (
    cgroup2_mount,
    cgroup_joinable,
    create_cgroup,
    join_cgroup,
    own_cgroup,
    remove_cgroup,
)


def cgroup_or_skip(name: str) -> str:
    try:
        return create_cgroup(name)
    except OSError as exc:
        pytest.skip(f"no cgroup can be created here: {exc}")


def test_a_new_cgroup_below_our_own_is_joinable_and_a_child_really_joins_it():
    path = cgroup_or_skip(f"joshua-test-{os.getpid()}")
    leaf = os.path.join(path, "node")
    os.mkdir(leaf)
    try:
        assert cgroup_joinable(leaf, os.path.join(cgroup2_mount(), own_cgroup().lstrip("/")))
        pid = os.fork()
        if pid == 0:
            code = 1  # the check said yes: the move must not fail
            try:
                join_cgroup(leaf)
                code = 0
            finally:
                os._exit(code)
        _, status = os.waitpid(pid, 0)
        assert os.waitstatus_to_exitcode(status) == 0
    finally:
        os.rmdir(leaf)
        remove_cgroup(path)


def test_a_directory_that_is_no_cgroup_is_not_joinable(tmp_path):
    (tmp_path / "cgroup.procs").write_text("")
    assert not cgroup_joinable(str(tmp_path), str(tmp_path))
