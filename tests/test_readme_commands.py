"""The README's runnable command blocks work as written, each in a new login shell of a fresh home.

The blocks (marked `<!-- test: run -->`, see testsupport/readme_blocks.py) run in file order from
the repository root, sharing one temporary HOME.
"""

import re
import subprocess
import tomllib

from testsupport.joshuac_cli import ROOT
from testsupport.readme_blocks import fresh_home, home_env, run_blocks, runnable_blocks


def test_the_marker_finds_the_set_up_blocks():
    blocks = runnable_blocks(ROOT / "README.md")
    assert blocks[0].strip() == "make install"
    assert any("joshuac " in block for block in blocks[1:])


def test_every_runnable_readme_block_succeeds_in_a_new_login_shell(tmp_path):
    home = fresh_home(tmp_path)
    env = home_env(home)
    run_blocks(ROOT / "README.md", ROOT, env)
    wrapper = home / ".local" / "bin" / "joshuac"
    assert str(ROOT / ".venv" / "bin" / "joshuac") in wrapper.read_text()
    subprocess.run(["bash", "-l", "-c", "make -s uninstall"], cwd=ROOT, env=env, check=True, capture_output=True)
    assert not wrapper.exists()
    assert "joshuac make install" not in (home / ".profile").read_text()


def test_make_install_wraps_every_console_script():
    scripts = set()
    for pyproject in (ROOT / "pyproject.toml", ROOT / "runtime" / "pyproject.toml"):
        scripts |= set(tomllib.loads(pyproject.read_text())["project"]["scripts"])
    listed = re.search(r"^COMMANDS=\(([^)]*)\)", (ROOT / "scripts" / "install.sh").read_text(), re.M)
    assert set(listed.group(1).split()) == scripts
