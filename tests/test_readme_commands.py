"""The README's runnable command blocks work as written, each in a new login shell of a fresh home.

A block is runnable when the line before its ```sh fence is `<!-- test: run -->`. Blocks run in file
order from the repository root, with `bash -l -e`, sharing one temporary HOME (so a later block sees
what an earlier one installed there, as a new terminal would). The home gets only the uv the machine
already has, and uv's cache is shared, so nothing is downloaded.
"""

import os
import re
import shutil
import subprocess
from pathlib import Path

from testsupport.joshuac_cli import ROOT

MARKER = "<!-- test: run -->"
RUNNABLE = re.compile(r"^" + re.escape(MARKER) + r"\n```sh\n(.*?)^```$", re.MULTILINE | re.DOTALL)
BLOCK_TIMEOUT_S = 300


def runnable_blocks(text: str) -> list[str]:
    return RUNNABLE.findall(text)


def fresh_home(tmp_path: Path) -> Path:
    home = tmp_path / "home"
    (home / ".local" / "bin").mkdir(parents=True)
    uv = shutil.which("uv", path=f"{Path.home() / '.local' / 'bin'}:{os.environ.get('PATH', '')}")
    assert uv, "uv is not installed (make setup installs it)"
    (home / ".local" / "bin" / "uv").symlink_to(uv)
    return home


def test_the_marker_finds_the_set_up_blocks():
    blocks = runnable_blocks((ROOT / "README.md").read_text())
    assert blocks[0].strip() == "make install"
    assert any("joshuac " in block for block in blocks[1:])


def test_every_runnable_readme_block_succeeds_in_a_new_login_shell(tmp_path):
    home = fresh_home(tmp_path)
    env = {
        "HOME": str(home),
        "USER": os.environ.get("USER", "root"),
        "LANG": "C.UTF-8",
        "UV_CACHE_DIR": os.environ.get("UV_CACHE_DIR", str(Path.home() / ".cache" / "uv")),
    }
    for block in runnable_blocks((ROOT / "README.md").read_text()):
        result = subprocess.run(
            ["bash", "-l", "-e", "-c", block],
            check=False,
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=BLOCK_TIMEOUT_S,
        )
        assert result.returncode == 0, f"README block failed:\n{block}\n{result.stdout}\n{result.stderr}"
    wrapper = home / ".local" / "bin" / "joshuac"
    assert str(ROOT / ".venv" / "bin" / "joshuac") in wrapper.read_text()
    subprocess.run(["bash", "-l", "-c", "make -s uninstall"], cwd=ROOT, env=env, check=True, capture_output=True)
    assert not wrapper.exists()
    assert "joshuac make install" not in (home / ".profile").read_text()
