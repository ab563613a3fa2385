"""Per-rule fixtures: tests/rules/<CODE>/bad.pbtxt (and overrides.txt) give exactly expected.txt.

Refresh after a deliberate message change (then review the diff):
    JOSHUA_UPDATE_FIXTURES=1 .venv/bin/pytest tests/rules/test_rule_fixtures.py
"""

import os
import re
from pathlib import Path

import pytest

from joshua_codegen.check import check_file
from joshua_codegen.diagnostics import format_text
from joshua_codegen.rules import HEADINGS, all_rules, explain

FIXTURES = Path(__file__).parent
UPDATE = os.environ.get("JOSHUA_UPDATE_FIXTURES") == "1"
REFRESH = "JOSHUA_UPDATE_FIXTURES=1 .venv/bin/pytest tests/rules/test_rule_fixtures.py"
CODES = [module.CODE for module in all_rules()]


def run_fixture(directory: Path, monkeypatch) -> tuple[str, list]:
    monkeypatch.chdir(directory)
    overrides_file = directory / "overrides.txt"
    overrides = overrides_file.read_text().splitlines() if overrides_file.exists() else []
    result = check_file("bad.pbtxt", overrides)
    return format_text(result.diagnostics, result.sources), result.diagnostics


@pytest.mark.parametrize("code", CODES)
def test_fixture_gives_exactly_the_expected_diagnostics(code, monkeypatch):
    directory = FIXTURES / code
    text, diagnostics = run_fixture(directory, monkeypatch)
    expected_file = directory / "expected.txt"
    if UPDATE:
        expected_file.write_text(text)
    assert text == expected_file.read_text(), f"{code} diagnostics changed; if intended, run: {REFRESH}"
    assert code in {d.code for d in diagnostics}


@pytest.mark.parametrize("code", CODES)
def test_every_rule_is_documented_and_has_a_fixture(code):
    module = next(m for m in all_rules() if m.CODE == code)
    doc = module.__doc__ or ""
    assert doc.startswith(f"{code} {module.NAME}: ")
    positions = [doc.find(f"\n{heading}:\n") for heading in HEADINGS]
    assert all(p > 0 for p in positions) and positions == sorted(positions), f"{code} lacks the headings {HEADINGS}"
    assert re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", module.NAME)
    assert module.SEVERITY == ("error" if code.startswith("E") else "warning")
    assert module.STAGE in ("load", "override", "check", "plan", "fleet")
    assert module.STAGE not in ("check", "plan", "fleet") or callable(module.check)
    assert module.__name__.rsplit(".", 1)[1].startswith(code.lower() + "_" + module.NAME.replace("-", "_"))
    assert (FIXTURES / code / "bad.pbtxt").exists()
    assert (FIXTURES / code / "expected.txt").exists()
    assert explain(code).startswith(doc.splitlines()[0])


def test_every_fixture_directory_belongs_to_a_registered_rule():
    directories = {p.name for p in FIXTURES.iterdir() if p.is_dir() and re.fullmatch(r"[EW]\d{3}", p.name)}
    assert directories == set(CODES)


def test_explain_accepts_lower_case_and_rejects_unknown_codes():
    assert explain("e301") == explain("E301")
    assert "Severity: error" in explain("E301")
    assert explain("E999") is None


@pytest.mark.process
def test_explain_without_a_code_lists_every_code_with_its_name():
    from testsupport.joshuac_cli import joshuac

    result = joshuac("explain")
    assert result.returncode == 0
    lines = result.stdout.splitlines()
    assert [line.split()[0] for line in lines] == CODES
    assert lines[CODES.index("E122")].split()[:3] == ["E122", "unsupported-policy-type", "error"]
    assert lines[CODES.index("E122")].endswith("an INFERENCE node's policy_type is not one the runtime can run.")
