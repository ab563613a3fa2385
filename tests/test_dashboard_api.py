"""The dashboard's API is written once: the schema document, the names the server's code takes from it, the
page's TypeScript types rendered from it, and the supervisor's refusal kinds the control client names."""

import json
import re

from jsonschema import Draft202012Validator

from joshua_codegen.supervisor.control_request import REFUSAL_KINDS as SUPERVISOR_REFUSAL_KINDS
from joshua_runtime.ai import episode_protocol
from joshua_runtime.dashboard import api_schema, api_typescript, control_client, robot_view, zenoh_link
from joshua_runtime.dashboard.app import CONTROL_ERROR_STATUS
from joshua_runtime.dashboard.fleet_roster import listed_fields
from joshua_runtime.dashboard.fleet_status import NodeStatus, RobotStatus

REFRESH_TYPES = "make api-types"


def test_the_control_client_names_every_refusal_of_the_supervisor():
    assert set(control_client.REFUSAL_KINDS) == set(SUPERVISOR_REFUSAL_KINDS), (
        "control_client.REFUSAL_KINDS and the supervisor's (joshua_codegen/supervisor/control_request.py) differ"
    )


def test_every_error_kind_is_the_schemas_and_has_an_http_status():
    assert sorted(control_client.ERROR_KINDS) == sorted(api_schema.enum("ErrorKind"))
    assert set(CONTROL_ERROR_STATUS) == set(control_client.ERROR_KINDS)


def test_the_schema_is_json_schema_with_a_major_minor_version():
    Draft202012Validator.check_schema(api_schema.SCHEMA)
    assert re.fullmatch(r"\d+\.\d+", api_schema.VERSION)


def test_every_route_and_event_refers_to_a_definition_of_the_schema():
    definitions = api_schema.SCHEMA["$defs"]
    references = [reply for route in api_schema.SCHEMA["routes"].values() for reply in route["replies"].values()]
    references += list(api_schema.SCHEMA["events"].values())
    for reference in references:
        if isinstance(reference, dict):
            assert reference["$ref"].removeprefix("#/$defs/") in definitions, reference


def test_stream_kinds_and_forwarded_events_are_the_schemas():
    kinds = {*robot_view.STREAM_KINDS.values(), robot_view.RATE}
    assert kinds == set(api_schema.enum("StreamKind"))
    assert set(zenoh_link.PUBLISHED_KINDS) <= set(api_schema.EVENT_KINDS)


def test_episode_commands_and_phases_are_the_recorders():
    assert api_schema.enum("EpisodeAction") == episode_protocol.COMMANDS
    assert api_schema.enum("RecorderPhase") == episode_protocol.PHASES


def test_the_fleet_views_entries_hold_the_fields_its_status_schema_keeps():
    definitions = api_schema.SCHEMA["$defs"]
    assert set(definitions["FleetNodeStatus"]["properties"]) == set(NodeStatus.model_fields)
    listed = json.loads(b"{" + listed_fields(RobotStatus()) + b"}")  # a status as the roster lists it
    assert set(listed) == set(RobotStatus.model_fields) - {"robot", "run"} | {"release", "health"}
    assert set(definitions["FleetRobot"]["properties"]) == set(listed) | {"name", "last_seen_s", "online", "rollout"}


def test_the_pages_types_are_rendered_from_the_schema():
    committed = api_typescript.TYPES_PATH.read_text(encoding="utf-8")
    assert committed == api_typescript.render(api_schema.SCHEMA), (
        f"{api_typescript.TYPES_PATH.name} is stale; refresh with: {REFRESH_TYPES}"
    )
