"""The runnable command blocks of a document (marked `<!-- test: run -->`), run in order as written in a fresh home.

A block is runnable when the line before its ```sh fence is the marker; a marker anywhere else is a
mistake that `misplaced_markers` finds (the block after it would silently never run). The blocks of
one document (README.md, CONTRIBUTING.md, docs/*.md: testsupport/documents.py) run in file order,
each with `bash -e` (a login shell by default), sharing one temporary HOME, so a later block sees
what an earlier one left there, as a new terminal would. The home gets only the uv
the machine already has, and uv's cache is shared, so nothing is downloaded.
"""

import os
import re
import shutil
import subprocess
from pathlib import Path

MARKER = "<!-- test: run -->"
RUNNABLE = re.compile(r"^" + re.escape(MARKER) + r"\n```sh\n(.*?)^```$", re.MULTILINE | re.DOTALL)
# A command block that needs what the tests may not use (a download from the Hugging Face Hub): shown, not run.
NETWORK_MARKER = "<!-- test: needs network -->"
NETWORK_ONLY = re.compile(r"^" + re.escape(NETWORK_MARKER) + r"\n```sh\n(.*?)^```$", re.MULTILINE | re.DOTALL)
BLOCK_TIMEOUT_S = 300
SUITE_SETTINGS = ("OMP_NUM_THREADS",)  # what the test suite sets for every process it starts (conftest.py)


def runnable_blocks(document: Path) -> list[str]:
    return RUNNABLE.findall(Path(document).read_text())


def network_only_blocks(document: Path) -> list[str]:
    return NETWORK_ONLY.findall(Path(document).read_text())


def misplaced_markers(document: Path) -> list[int]:
    """Line numbers of the markers not followed at once by a ```sh fence."""
    lines = Path(document).read_text().splitlines()
    return [
        number
        for number, line in enumerate(lines, 1)
        if line.strip() == MARKER and (number == len(lines) or lines[number] != "```sh")
    ]


def fresh_home(tmp_path: Path) -> Path:
    home = tmp_path / "home"
    (home / ".local" / "bin").mkdir(parents=True)
    uv = shutil.which("uv", path=f"{Path.home() / '.local' / 'bin'}:{os.environ.get('PATH', '')}")
    assert uv, "uv is not installed (make setup installs it)"
    (home / ".local" / "bin" / "uv").symlink_to(uv)
    return home


def home_env(home: Path, **extra: str) -> dict:
    """A minimal environment of a user whose home is `home` (uv's cache shared with this machine's, the
    suite's thread limit kept)."""
    return {
        "HOME": str(home),
        "USER": os.environ.get("USER", "root"),
        "LANG": "C.UTF-8",
        "UV_CACHE_DIR": os.environ.get("UV_CACHE_DIR", str(Path.home() / ".cache" / "uv")),
        **{name: os.environ[name] for name in SUITE_SETTINGS if name in os.environ},
        **extra,
    }


def run_blocks(document: Path, cwd: Path, env: dict, login: bool = True) -> list[subprocess.CompletedProcess]:
    """Run every runnable block of `document` in order; fail the test at the first that fails."""
    shell = ["bash", "-l", "-e", "-c"] if login else ["bash", "-e", "-c"]
    results = []
    for block in runnable_blocks(document):
        result = subprocess.run(
            [*shell, block], check=False, cwd=cwd, env=env, capture_output=True, text=True, timeout=BLOCK_TIMEOUT_S
        )
        assert result.returncode == 0, f"{Path(document).name} block failed:\n{block}\n{result.stdout}\n{result.stderr}"
        results.append(result)
    return results
