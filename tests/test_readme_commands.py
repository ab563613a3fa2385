"""The README's runnable command blocks work as written, each in a new login shell of a fresh home.

The blocks (marked `<!-- test: run -->`, see testsupport/readme_blocks.py) run in file order from
the repository root, sharing one temporary HOME.
"""

import subprocess
import tomllib

import pytest

from testsupport.joshuac_cli import ROOT
from testsupport.readme_blocks import fresh_home, home_env, run_blocks, runnable_blocks

MARK = "# joshuac make install"  # on every wrapper and PATH line scripts/install.sh writes


def test_the_marker_finds_the_set_up_blocks():
    blocks = runnable_blocks(ROOT / "README.md")
    assert blocks[0].strip() == "make install"
    assert any("joshuac " in block for block in blocks[1:])


@pytest.mark.process
@pytest.mark.xdist_group("checkout")  # `make install` sets the checkout up
def test_every_runnable_readme_block_succeeds_in_a_new_login_shell(tmp_path):
    home = fresh_home(tmp_path)
    env = home_env(home)
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
