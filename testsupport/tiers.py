"""The tier of every test (what it needs to run), given as pytest marks so that `-m` selects by it, and the
xdist group of tests that must share a worker of `make test`.

A test's tiers come from the fixtures it uses (a fact: `ros_env` means a ROS domain) and from the
default of its directory (`DIRECTORY_TIERS`). Tier marks written on a test or its module replace the
directory's default; they are needed only where that default is wrong. `unit` means nothing else: a
test with any other tier is not a unit test. A test whose directory has no default and whose
fixtures say nothing has no tier: tests/test_tiers.py fails and names it.
"""

from pathlib import Path

import pytest

# Each tier, registered in pyproject.toml ([tool.pytest.ini_options] markers) with what it means.
UNIT, PROCESS, ROS, BROWSER, AI, BENCH, CONTAINER = "unit", "process", "ros", "browser", "ai", "bench", "container"
TIERS = (UNIT, PROCESS, ROS, BROWSER, AI, BENCH, CONTAINER)

# Fixtures that decide a tier wherever they are used (directly or through another fixture).
FIXTURE_TIERS = {
    "ros_env": (ROS,),  # also behind ros_domain, ros_client, start_node, ai_env, ros_peer, start_cpp
    "start_node": (PROCESS,),
    "start_cpp": (PROCESS,),
    "page": (BROWSER,),  # a Playwright page
    "ai_env": (AI,),
    "lerobot_offline": (AI,),
    "trained_reach": (AI,),
}

# The tier of a test file's directory (relative to the repository root) when its fixtures and marks say
# nothing more. A new test directory gets a line here.
DIRECTORY_TIERS = {
    "tests": UNIT,
    "tests/rules": UNIT,
    "tests/supervisor": UNIT,
    "tests/process": PROCESS,
    "tests/e2e": PROCESS,
    "tests/fleet": PROCESS,  # joshuac, ansible-playbook, openssl and the robot-side release tool as processes
    "tests/containers": CONTAINER,
    "runtime/tests": UNIT,
    "runtime/tests/ai": AI,
    "runtime/tests/bags": UNIT,
    "runtime/tests/cpp": PROCESS,
    "runtime/tests/dashboard": UNIT,
    "runtime/tests/description": UNIT,
    "runtime/tests/desktop": UNIT,
    "runtime/tests/foxglove": UNIT,
    "runtime/tests/hosts": PROCESS,
    "runtime/tests/interfaces": UNIT,
    "runtime/tests/interpreters": PROCESS,  # fresh environments of other Pythons, install.sh runs
    "runtime/tests/lego": UNIT,
    "runtime/tests/multihost": PROCESS,  # simulated computers: network namespaces and the processes in them
    "runtime/tests/node_starter": PROCESS,  # a starter process and the nodes it forks
    "runtime/tests/rollout": UNIT,
    "runtime/tests/sensors": UNIT,
    "runtime/tests/servo": UNIT,
    "runtime/tests/sim": UNIT,
    "runtime/tests/tools": UNIT,
    "runtime/tests/train": AI,
}

# Fixtures made once per worker process that cost more than the tests using them: those tests run on one
# worker (an xdist_group named after the fixture), so that `make test` makes each once.
SHARED_FIXTURES = ("trained_reach", "bundle", "podman", "runtime_environments")  # podman: the container tests' images

# A fixture of these scopes is made once per worker that runs a test of its module: such a module's tests
# share a worker (an xdist_group named after the module).
MODULE_SCOPES = ("class", "module", "package")

UNTIERED = pytest.StashKey[list]()  # node ids of the collected tests that got no tier


def tiers_of(item: pytest.Item, root: Path) -> set[str]:
    """The tiers of one collected test (see the module docstring)."""
    tiers = {mark.name for mark in item.iter_markers() if mark.name in TIERS}
    if not tiers:
        directory = item.path.parent.relative_to(root).as_posix() if item.path.is_relative_to(root) else ""
        tiers = {DIRECTORY_TIERS[directory]} if directory in DIRECTORY_TIERS else set()
    for fixture in getattr(item, "fixturenames", ()):
        tiers.update(FIXTURE_TIERS.get(fixture, ()))
    if len(tiers) > 1:
        tiers.discard(UNIT)
    return tiers


def shared_group(item: pytest.Item) -> str | None:
    """The xdist group of a test that uses a fixture made once for several tests (None: any worker)."""
    names = getattr(item, "fixturenames", ())
    shared = [name for name in SHARED_FIXTURES if name in names]
    if shared:
        return shared[0]
    info = getattr(item, "_fixtureinfo", None)
    definitions = info.name2fixturedefs.values() if info is not None else ()
    if any(defs and defs[-1].scope in MODULE_SCOPES for defs in definitions):
        return item.nodeid.split("::")[0]
    return None


@pytest.hookimpl(tryfirst=True)  # before `-m` deselects: every collected test is tiered and checked
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    untiered = []
    grouping = config.pluginmanager.hasplugin("xdist")  # the mark is xdist's (other Pythons' runs lack it)
    for item in items:
        tiers = tiers_of(item, config.rootpath)
        if not tiers:
            untiered.append(item.nodeid)
        for tier in sorted(tiers):
            if not item.get_closest_marker(tier):
                item.add_marker(tier)
        group = shared_group(item) if grouping else None
        if group and not item.get_closest_marker("xdist_group"):
            item.add_marker(pytest.mark.xdist_group(group))
    config.stash[UNTIERED] = untiered
