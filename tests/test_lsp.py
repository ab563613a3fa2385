"""`joshuac lsp` driven by a real LSP client (pytest-lsp) over stdio, as an editor drives it."""

import json
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

from testsupport.joshuac_cli import ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac lsp

SERVER = [sys.executable, "-m", "joshua_codegen", "lsp"]
DESCRIPTION = """\
robot_config {
  name: "arm"
  mode: MODE_TELEOPERATION

  node {
    name: "leader"
    type: MOCK_ENCODER_PUBLISHER
    topic_name: "/leader/joint_states"
    qos_reliability: BEST_EFFORT
  }

  node {
    name: "follower"
    type: MOCK_ACTUATOR_SUBSCRIBER
    topic_name: "/leader/joint_states"
    qos_dept: 5
  }

  node {
    name: "recorder"
    type: DATA_SUBSCRIBER
    topic_name: "/leader/joint_states"
    input_topics: ["/leader/joint_states"]
    qos_reliability: BEST_EFORT
    output_directory: "/data"
  }

  node {
    name: "broken"
    type: CAMERA_PUBLISHER
    topic_name: "/camera" "
  }
}
"""


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER, server_env={"PYTHONPATH": str(ROOT)}))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(
        types.InitializeParams(capabilities=pytest_lsp.client_capabilities("visual-studio-code"))
    )
    yield
    await lsp_client.shutdown_session()


def _line(text: str, needle: str) -> int:
    """0-based line of the first line holding `needle`."""
    return next(i for i, line in enumerate(text.split("\n")) if needle in line)


def _position(text: str, needle: str, offset: int = 0) -> types.Position:
    line = _line(text, needle)
    return types.Position(line, text.split("\n")[line].index(needle) + offset)


async def _open(client: LanguageClient, path: Path, text: str) -> str:
    path.write_text(text)
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(uri, "pbtxt", 1, text)))
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return uri


def _expected(path: Path) -> list[tuple[str, int, int, int, int]]:
    """(code, line, column, end line, end column) of `joshuac check --format json`, 0-based as LSP counts."""
    document = json.loads(joshuac("check", "--format", "json", path, cwd=ROOT).stdout)
    expected = []
    for d in document["diagnostics"]:
        end_line = d["end_line"] if d["end_line"] is not None else d["line"]
        end_column = d["end_column"] if d["end_column"] is not None else d["column"] + 1
        expected.append((d["code"], d["line"] - 1, d["column"] - 1, end_line - 1, end_column - 1))
    return expected


def _seen(diagnostics) -> list[tuple[str, int, int, int, int]]:
    return [
        (d.code, d.range.start.line, d.range.start.character, d.range.end.line, d.range.end.character)
        for d in diagnostics
    ]


@pytest.mark.asyncio
async def test_diagnostics_are_those_of_check_as_the_text_changes(client, tmp_path):
    path = tmp_path / "arm.pbtxt"
    uri = await _open(client, path, DESCRIPTION)
    seen = _seen(client.diagnostics[uri])
    assert seen == _expected(path)
    assert {"E001", "E002", "E004"} <= {code for code, *_ in seen}  # recovery: every node's problem at once
    assert all(d.source == "joshuac" for d in client.diagnostics[uri])

    # Fix the syntax error and the two typos: a graph rule (QoS across nodes) now speaks.
    fixed = (
        DESCRIPTION.replace('"/camera" "', '"/camera"')
        .replace("qos_dept", "qos_depth")
        .replace("BEST_EFORT", "RELIABLE")
    )
    line = _line(DESCRIPTION, '"/camera" "')
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(version=2, uri=uri),
            [
                types.TextDocumentContentChangePartial(
                    types.Range(types.Position(0, 0), types.Position(line + 3, 0)), fixed
                )
            ],
        )
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    path.write_text(fixed)
    seen = _seen(client.diagnostics[uri])
    assert seen == _expected(path)
    assert "E301" in {code for code, *_ in seen}  # the recorder requires RELIABLE, the leader offers BEST_EFFORT


@pytest.mark.asyncio
async def test_hover_shows_the_schema_and_the_explanation(client, tmp_path):
    uri = await _open(client, tmp_path / "arm.pbtxt", DESCRIPTION)

    async def hover(needle, offset=1):
        params = types.HoverParams(types.TextDocumentIdentifier(uri), _position(DESCRIPTION, needle, offset))
        result = await client.text_document_hover_async(params)
        return result.contents.value if result is not None else None

    assert "Topic the node publishes" in await hover("topic_name")
    assert "DDS reliability" in await hover("BEST_EFFORT")  # the enum's meaning
    assert "Synthetic stand-ins" in await hover("MOCK_ENCODER_PUBLISHER")
    unknown_field = await hover("qos_dept")
    assert "E002" in unknown_field and "What it checks" in unknown_field
    assert await hover("robot_config", 20) is None  # past the end of the line: nothing to say


@pytest.mark.asyncio
async def test_completion_offers_what_fits_the_cursor(client, tmp_path):
    text = DESCRIPTION.replace(
        '    output_directory: "/data"\n',
        '    output_directory: "/data"\n    qos_\n    input_topics: ["\n    restart: \n',
    )
    uri = await _open(client, tmp_path / "arm.pbtxt", text)

    async def labels(line_needle, column):
        line = _line(text, line_needle)
        params = types.CompletionParams(types.TextDocumentIdentifier(uri), types.Position(line, column))
        result = await client.text_document_completion_async(params)
        return [item.label for item in result.items]

    assert await labels("    qos_\n".strip(), 8) == ["qos_depth", "qos_reliability", "qos_durability", "qos_history"]
    assert await labels('input_topics: ["\n'.strip(), 20) == ["/leader/joint_states"]
    assert await labels("restart: ", 13) == ["RESTART_NEVER", "RESTART_ON_FAILURE", "RESTART_ALWAYS"]
    mode = await labels("mode: MODE_TELEOPERATION", 8)
    assert mode == [
        "MODE_TELEOPERATION",
        "MODE_SIMULATION",
        "MODE_INFERENCE",
        "MODE_DATA_COLLECTION",
        "MODE_CALIBRATION",
    ]
    assert "node" in await labels('name: "arm"', 2) and "qos_depth" not in await labels('name: "arm"', 2)


@pytest.mark.asyncio
async def test_definition_goes_from_a_subscription_to_its_publishers(client, tmp_path):
    text = (
        DESCRIPTION.replace('"/camera" "', '"/camera"')
        .replace("qos_dept", "qos_depth")
        .replace("BEST_EFORT", "RELIABLE")
    )
    uri = await _open(client, tmp_path / "arm.pbtxt", text)
    line = _line(text, 'input_topics: ["/leader')
    params = types.DefinitionParams(types.TextDocumentIdentifier(uri), types.Position(line, 24))
    (found,) = await client.text_document_definition_async(params)
    assert found.uri == uri and found.range.start == types.Position(_line(text, '"/leader/joint_states"'), 4)
    on_publisher = types.DefinitionParams(types.TextDocumentIdentifier(uri), types.Position(found.range.start.line, 20))
    assert await client.text_document_definition_async(on_publisher) is None  # a publisher is the definition


@pytest.mark.asyncio
async def test_formatting_is_fmt(client, tmp_path):
    text = DESCRIPTION.replace('"/camera" "', '"/camera"').replace("  node {\n    name", "node {  name", 1)
    path = tmp_path / "arm.pbtxt"
    uri = await _open(client, path, text)
    params = types.DocumentFormattingParams(types.TextDocumentIdentifier(uri), types.FormattingOptions(2, True))
    (edit,) = await client.text_document_formatting_async(params)
    assert edit.range.start == types.Position(0, 0) and edit.new_text == joshuac("fmt", path).stdout != text


@pytest.mark.asyncio
async def test_code_actions_apply_the_did_you_mean_fixes(client, tmp_path):
    uri = await _open(client, tmp_path / "arm.pbtxt", DESCRIPTION)
    whole = types.Range(types.Position(0, 0), types.Position(len(DESCRIPTION.split("\n")), 0))
    params = types.CodeActionParams(types.TextDocumentIdentifier(uri), whole, types.CodeActionContext([]))
    actions = await client.text_document_code_action_async(params)
    edits = {action.diagnostics[0].code: action.edit.changes[uri][0] for action in actions}
    assert set(edits) == {"E002", "E004"}
    assert edits["E002"].new_text == "qos_depth" and edits["E002"].range.start == _position(DESCRIPTION, "qos_dept")
    assert edits["E004"].new_text == "BEST_EFFORT" and edits["E004"].range.start == _position(DESCRIPTION, "BEST_EFORT")
