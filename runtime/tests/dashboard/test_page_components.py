"""The page's component tests (vitest, in web/src/test/) run as part of the suite."""

import shutil
import subprocess
from pathlib import Path

import pytest

pytestmark = [pytest.mark.process, pytest.mark.xdist_group("checkout")]  # vitest on web/, which setup rebuilds

WEB = Path(__file__).resolve().parents[3] / "web"
VITEST_TIMEOUT_S = 180


def test_page_components_pass_their_vitest_tests():
    assert shutil.which("npx"), "npm is missing: run `make setup`"
    assert (WEB / "node_modules").is_dir(), "web/node_modules is missing: run `make setup`"
    result = subprocess.run(
        ["npx", "--no-install", "vitest", "run", "--reporter=dot"],
        cwd=WEB,
        capture_output=True,
        text=True,
        timeout=VITEST_TIMEOUT_S,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr
