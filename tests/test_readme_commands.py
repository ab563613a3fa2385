"""The runnable command blocks of README.md, CONTRIBUTING.md and docs/*.md work as written, in a fresh home.

The blocks (marked `<!-- test: run -->`, see testsupport/readme_blocks.py) of one document run in file
order from the repository root, sharing one temporary HOME. The README's begin with `make install`
and run in new login shells (its first robot in a ROS domain of its own); the other documents are read
after it, so their blocks run in a shell with the checkout's commands first on PATH (its .venv/bin,
where `make install`'s wrappers lead; a login shell of root would reset PATH) and join a ROS domain of
their own.
"""

import os
import subprocess
import tomllib

import pytest

from testsupport.documents import documents
from testsupport.joshuac_cli import ROOT
from testsupport.readme_blocks import fresh_home, home_env, misplaced_markers, run_blocks, runnable_blocks

# The documents besides the README that hold runnable blocks, each run as one test.
OTHER_RUNNABLE = [path for path in documents()[1:] if path.exists() and runnable_blocks(path)]

MARK = "# joshuac make install"  # on every wrapper and PATH line scripts/install.sh writes


def test_the_marker_finds_the_set_up_blocks():
    blocks = runnable_blocks(ROOT / "README.md")
    assert blocks[0].strip() == "make install"
    assert any("joshuac " in block for block in blocks[1:])


@pytest.mark.process
@pytest.mark.xdist_group("checkout")  # `make install` sets the checkout up
def test_every_runnable_readme_block_succeeds_in_a_new_login_shell(tmp_path, ros_env):
    home = fresh_home(tmp_path)
    env = home_env(
        home,
        ROS_DOMAIN_ID=ros_env["ROS_DOMAIN_ID"],
        ROS_AUTOMATIC_DISCOVERY_RANGE=ros_env["ROS_AUTOMATIC_DISCOVERY_RANGE"],
    )
    run_blocks(ROOT / "README.md", ROOT, env)
    bindir = home / ".local" / "bin"
    wrapper = bindir / "joshuac"
    assert str(ROOT / ".venv" / "bin" / "joshuac") in wrapper.read_text()
    assert {path.name for path in bindir.iterdir() if MARK in path.read_text(errors="replace")} == console_scripts()
    subprocess.run(["bash", "-l", "-c", "make -s uninstall"], cwd=ROOT, env=env, check=True, capture_output=True)
    assert not wrapper.exists()
    assert not console_scripts() & {path.name for path in bindir.iterdir()}
    assert MARK not in (home / ".profile").read_text()


def console_scripts() -> set[str]:
    """The commands the project's packages declare."""
    scripts = set()
    for pyproject in (ROOT / "pyproject.toml", ROOT / "runtime" / "pyproject.toml"):
        scripts |= set(tomllib.loads(pyproject.read_text())["project"]["scripts"])
    return scripts


@pytest.mark.parametrize("document", documents(), ids=lambda path: str(path.relative_to(ROOT)))
def test_every_marker_stands_right_before_a_sh_block(document):
    """A marker followed by anything but a ```sh fence would leave its block silently untested."""
    if document.exists():
        assert misplaced_markers(document) == [], f"{document.name}: markers not followed by ```sh"


def test_a_marker_before_anything_but_a_sh_block_is_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- test: run -->\n```sh\ntrue\n```\n\n<!-- test: run -->\n```bash\ntrue\n```\n<!-- test: run -->\n"
    )
    assert runnable_blocks(page) == ["true\n"]
    assert misplaced_markers(page) == [6, 10]


@pytest.mark.process
@pytest.mark.parametrize("document", OTHER_RUNNABLE, ids=lambda path: str(path.relative_to(ROOT)))
def test_every_runnable_block_of_the_other_documents_succeeds(document, tmp_path, ros_env):
    env = home_env(
        fresh_home(tmp_path),
        PATH=f"{ROOT / '.venv' / 'bin'}:{os.environ['PATH']}",
        ROS_DOMAIN_ID=ros_env["ROS_DOMAIN_ID"],
        ROS_AUTOMATIC_DISCOVERY_RANGE=ros_env["ROS_AUTOMATIC_DISCOVERY_RANGE"],
    )
    assert run_blocks(document, ROOT, env, login=False)
