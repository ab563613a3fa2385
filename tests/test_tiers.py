"""Every test has a tier (testsupport/tiers.py), so `make test-fast` and `-m` selections miss none by accident."""

from pathlib import Path
from types import SimpleNamespace

import pytest

from testsupport.tiers import DIRECTORY_TIERS, TIERS, UNTIERED, shared_group, tiers_of

ROOT = Path("/checkout")


def test_every_collected_test_has_a_tier(pytestconfig):
    untiered = pytestconfig.stash[UNTIERED]
    assert not untiered, (
        f"{len(untiered)} tests have no tier: give their directory a default in DIRECTORY_TIERS of "
        "testsupport/tiers.py, or mark them (pytestmark = pytest.mark.unit, .process, ...):\n" + "\n".join(untiered)
    )


def test_every_tier_is_registered_with_pytest(pytestconfig):
    registered = {line.split(":")[0] for line in pytestconfig.getini("markers")}
    assert set(TIERS) <= registered, f"register {sorted(set(TIERS) - registered)} in pyproject.toml"


def test_every_directory_default_is_a_tier_and_exists():
    root = Path(__file__).resolve().parent.parent
    assert set(DIRECTORY_TIERS.values()) <= set(TIERS)
    assert [directory for directory in DIRECTORY_TIERS if not (root / directory).is_dir()] == []


def item(path: str, fixtures=(), marks=()):
    """A collected test as tiers_of sees it."""
    return SimpleNamespace(
        path=ROOT / path,
        fixturenames=list(fixtures),
        iter_markers=lambda: [getattr(pytest.mark, name).mark for name in marks],
    )


@pytest.mark.parametrize(
    ("path", "fixtures", "marks", "expected"),
    [
        ("tests/rules/test_x.py", ["tmp_path"], [], {"unit"}),
        ("tests/process/test_x.py", [], [], {"process"}),
        ("tests/test_x.py", ["ros_env", "ros_domain", "start_node"], [], {"ros", "process"}),
        ("runtime/tests/ai/test_x.py", ["ros_env", "ai_env"], [], {"ai", "ros"}),
        ("tests/test_x.py", [], ["process"], {"process"}),  # a mark replaces the directory's unit
        ("runtime/tests/ai/test_x.py", [], ["unit"], {"unit"}),
        ("tests/test_x.py", ["ros_env"], ["unit"], {"ros"}),  # what the fixtures need wins over a mark
        ("tests/new_directory/test_x.py", ["tmp_path"], [], set()),
        ("tests/new_directory/test_x.py", ["ros_env"], [], {"ros"}),
    ],
)
def test_tiers_come_from_marks_directory_and_fixtures(path, fixtures, marks, expected):
    assert tiers_of(item(path, fixtures, marks), ROOT) == expected


def grouped(fixture_scopes: dict[str, str], nodeid="tests/test_x.py::test_y"):
    """The xdist group of a test using fixtures of these scopes (name -> scope)."""
    definitions = {name: [SimpleNamespace(scope=scope)] for name, scope in fixture_scopes.items()}
    test = SimpleNamespace(
        nodeid=nodeid, fixturenames=list(fixture_scopes), _fixtureinfo=SimpleNamespace(name2fixturedefs=definitions)
    )
    return shared_group(test)


def test_tests_of_a_module_fixture_share_a_worker_and_shared_fixtures_their_group():
    assert grouped({"tmp_path": "function", "ros_env": "session"}) is None
    assert grouped({"trained": "module", "tmp_path": "function"}) == "tests/test_x.py"
    assert grouped({"recording": "class"}) == "tests/test_x.py"
    assert grouped({"podman": "session", "trained": "module"}) == "podman"  # a shared fixture names the group
