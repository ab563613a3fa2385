"""Paths of the repository and a way to run the joshuac command line, for the compiler tests."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = sorted((ROOT / "config" / "robots").glob("*.pbtxt"))
JOSHUAC = [sys.executable, "-m", "joshua_codegen"]


def joshuac(*args, cwd=None, env=None, check=False) -> subprocess.CompletedProcess:
    """Run the joshuac command line in a subprocess, as a user would."""
    return subprocess.run(
        [*JOSHUAC, *map(str, args)], cwd=cwd, env=env or dict(os.environ), capture_output=True, text=True, check=check
    )
