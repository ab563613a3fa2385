"""Committed artifacts match their sources: generated/<robot>/ and the schema's _pb2 modules."""

import filecmp
import subprocess

import pytest

from testsupport.joshuac_cli import CONFIGS, ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line

REFRESH_GENERATED = "make generate"
REFRESH_PROTO = "make proto"


@pytest.mark.parametrize("config", CONFIGS, ids=lambda p: p.stem)
def test_generated_tree_is_up_to_date(config):
    committed = ROOT / "generated" / config.stem
    assert committed.is_dir(), f"generated/{config.stem} is missing; refresh with: {REFRESH_GENERATED}"
    result = joshuac("build", config, "-o", committed, "--check", cwd=ROOT)
    assert result.returncode == 0, (
        f"generated/{config.stem} is stale; refresh with: {REFRESH_GENERATED}\n{result.stdout[:4000]}{result.stderr}"
    )


def test_every_generated_tree_has_a_description():
    robots = {p.name for p in (ROOT / "generated").iterdir() if p.is_dir()}
    assert robots == {c.stem for c in CONFIGS}, f"remove generated trees without a description; {REFRESH_GENERATED}"


def test_schema_modules_match_the_proto_files(tmp_path):
    subprocess.run(
        ["bash", "scripts/gen_proto.sh", str(tmp_path)],
        cwd=ROOT,
        check=True,
        capture_output=True,
        env={"PATH": f"{ROOT / '.venv' / 'bin'}:/usr/bin:/bin"},
    )
    fresh = sorted(p.name for p in tmp_path.iterdir())
    assert fresh
    committed = ROOT / "core" / "joshua_core" / "schema"
    _, mismatch, errors = filecmp.cmpfiles(tmp_path, committed, fresh, shallow=False)
    assert not mismatch and not errors, f"schema modules are stale ({mismatch + errors}); refresh with: {REFRESH_PROTO}"
