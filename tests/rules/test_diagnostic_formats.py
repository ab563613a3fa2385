"""Printed forms of diagnostics: text with carets and notes, stable JSON, GitHub annotations."""

import json

from joshua_codegen.check import check_text
from joshua_codegen.diagnostics import Diagnostic, Related, format_github, format_json, format_text, sort_diagnostics

SOURCE = 'robot_config {\n\tname: "x"\n  mode: MODE_X\n}\n'
QOS = Diagnostic(
    "b.pbtxt",
    3,
    9,
    "E301",
    "error",
    'publisher "cam" offers BEST_EFFORT, subscriber requires RELIABLE',
    3,
    15,
    (Related("b.pbtxt", 2, 2, "publisher declared here"),),
)
NAME = Diagnostic("b.pbtxt", 2, 2, "W101", "warning", "name: 100%, ok\nnext", 2, 11)
OTHER = Diagnostic("a.pbtxt", 9, 1, "E102", "error", "mode is not set")


def test_sort_is_by_path_line_column_code():
    same_spot = Diagnostic("b.pbtxt", 2, 2, "E101", "error", "z")
    assert sort_diagnostics([QOS, NAME, OTHER, same_spot]) == [OTHER, same_spot, NAME, QOS]


def test_text_form_has_source_lines_carets_notes_and_a_summary():
    text = format_text([QOS, NAME, OTHER], {"b.pbtxt": SOURCE})
    assert text == (
        "a.pbtxt:9:1: error[E102]: mode is not set\n"
        "b.pbtxt:2:2: warning[W101]: name: 100%, ok\\nnext\n"
        '\tname: "x"\n'
        "\t^~~~~~~~~\n"
        'b.pbtxt:3:9: error[E301]: publisher "cam" offers BEST_EFFORT, subscriber requires RELIABLE\n'
        "  mode: MODE_X\n"
        "        ^~~~~~\n"
        "b.pbtxt:2:2: note: publisher declared here\n"
        '\tname: "x"\n'
        "\t^\n"
        "2 errors, 1 warning\n"
    )


def test_text_form_summary_when_clean():
    assert format_text([], {}) == "0 errors, 0 warnings\n"


def test_json_form_is_stable_and_documented():
    document = json.loads(format_json([QOS, OTHER]))
    assert document == {
        "version": 1,
        "diagnostics": [
            {
                "path": "a.pbtxt",
                "line": 9,
                "column": 1,
                "end_line": None,
                "end_column": None,
                "code": "E102",
                "severity": "error",
                "message": "mode is not set",
                "related": [],
            },
            {
                "path": "b.pbtxt",
                "line": 3,
                "column": 9,
                "end_line": 3,
                "end_column": 15,
                "code": "E301",
                "severity": "error",
                "message": 'publisher "cam" offers BEST_EFFORT, subscriber requires RELIABLE',
                "related": [{"path": "b.pbtxt", "line": 2, "column": 2, "message": "publisher declared here"}],
            },
        ],
        "summary": {"errors": 2, "warnings": 0},
    }
    assert list(document["diagnostics"][0]) == [
        "path",
        "line",
        "column",
        "end_line",
        "end_column",
        "code",
        "severity",
        "message",
        "related",
    ]


def test_github_form_escapes_data_and_properties():
    weird_path = Diagnostic("dir,x:y/r%.pbtxt", 1, 1, "E001", "error", "bad")
    assert format_github([QOS, NAME, weird_path]) == (
        "::warning file=b.pbtxt,line=2,col=2,endLine=2,endColumn=10,title=W101::name: 100%25, ok%0Anext\n"
        '::error file=b.pbtxt,line=3,col=9,endLine=3,endColumn=14,title=E301::publisher "cam" offers '
        "BEST_EFFORT, subscriber requires RELIABLE (publisher declared here: b.pbtxt:2:2)\n"
        "::error file=dir%2Cx%3Ay/r%25.pbtxt,line=1,col=1,title=E001::bad\n"
    )


def test_long_lines_are_cut_around_the_caret():
    text = 'robot_config { name: "' + "a" * 500 + '" mode: MODE_X }'
    result = check_text("r.pbtxt", text)
    printed = format_text(result.diagnostics, result.sources).splitlines()
    assert printed[0].startswith("r.pbtxt:1:531: error[E004]")
    assert len(printed[1]) == 200
    assert printed[1][printed[2].index("^") :].startswith("MODE_X")
