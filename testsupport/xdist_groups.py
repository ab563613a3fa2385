"""Tests of one xdist_group run on one worker of `make test` (pytest-xdist's `--dist loadgroup`) on pytest 9.2 too.

xdist's worker tells its scheduler a test's group by a suffix on the test's node id (`path::test@group`),
which it adds by setting the item's `_nodeid`; pytest 9.2 keeps the id in `_id`, so the suffix never
showed, and every group was spread over the workers like tests without one (two workers each built the
same container image, benchmarks ran side by side). This adds the suffix where xdist's did not take.
"""

import os

import pytest


def group_suffix(item: pytest.Item) -> str:
    """`@name` of the test's xdist groups as xdist writes it (names sorted, joined by `_`), or ''."""
    names = {
        str(mark.args[0] if mark.args else mark.kwargs.get("name", "default"))
        for mark in item.iter_markers("xdist_group")
    }
    return f"@{'_'.join(sorted(names))}" if names else ""


@pytest.hookimpl(trylast=True)  # after every hook that marks groups, xdist's own included
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    # The worker's variable also reaches pytest runs a test starts, where xdist may not be installed.
    if not os.environ.get("PYTEST_XDIST_WORKER") or not config.getoption("loadgroup", False):
        return
    from _pytest.nodeid import coerce_node_id

    for item in items:
        suffix = group_suffix(item)
        if suffix and not item.nodeid.endswith(suffix):
            item._id = coerce_node_id(item.nodeid + suffix)
