"""The settings contract between joshuac and the runtime: typed, versioned, and refused in one line when it does not fit."""

import subprocess
import sys
from pathlib import Path

import pytest
from google.protobuf import json_format
from hypothesis import given, settings
from hypothesis import strategies as st

from joshua_codegen.compile import node_settings
from joshua_core.settings import FORMAT_VERSION, NodeSettings, SettingsFormatError, parse, to_literal

ROBOTS = sorted((Path(__file__).resolve().parents[2] / "config" / "robots").glob("*.pbtxt"))


def run_literal(literal: dict, env: dict) -> subprocess.CompletedProcess:
    code = f"import sys\nfrom joshua_runtime.entrypoint import run_node\nsys.exit(run_node({literal!r}))\n"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("robot", ROBOTS, ids=lambda path: path.stem)
def test_every_process_of_the_seed_robots_parses_back_into_its_message(robot):
    for name, literal in node_settings(robot.read_text(), path=str(robot)).items():
        settings = parse(literal)
        assert isinstance(settings, NodeSettings) and settings.name == name
        assert to_literal(settings) == literal


@settings(max_examples=200, deadline=None)
@given(
    number=st.floats(allow_nan=True, allow_infinity=True),
    text=st.text(max_size=8),
    count=st.integers(min_value=0, max_value=2**32 - 1),
    flag=st.booleans(),
)
def test_the_literal_is_what_protobufs_json_mapping_writes(number, text, count, flag):
    settings_message = NodeSettings(
        name=text,
        rate_hz=number,
        device_ids=[count, 0],
        joint_names=[text, ""],
        format_version=count,
        keep_torque_on_exit=flag,
    )
    settings_message.topic.qos.depth = count
    settings_message.inputs.add(name=text).qos.reliability = text
    settings_message.simulation.timestep_s = 0.0  # explicit presence: written although zero
    settings_message.simulation.simulates.add(name=text, rate_hz=-number, wheel_radius_m=number)
    settings_message.preset.add().positions.update({text: number, "": -number})
    settings_message.foxglove.port = count
    if flag:
        settings_message.simulation.realtime_factor = number
    assert to_literal(settings_message) == json_format.MessageToDict(settings_message, preserving_proto_field_name=True)


@pytest.mark.parametrize("version", [FORMAT_VERSION - 1, FORMAT_VERSION + 1, None])
def test_settings_of_another_version_exit_2_naming_both_versions(version, ros_env):
    literal = {"name": "old", "type": "MOCK_ENCODER_PUBLISHER"}
    if version is not None:
        literal["format_version"] = version
    result = run_literal(literal, ros_env)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert f"format version {version}" in result.stderr and f"reads version {FORMAT_VERSION}" in result.stderr


def test_a_field_the_contract_does_not_know_exits_2_naming_it(ros_env):
    result = run_literal(
        {
            "format_version": FORMAT_VERSION,
            "name": "n",
            "type": "MOCK_ENCODER_PUBLISHER",
            "serial_prot": "/dev/ttyUSB0",
        },
        ros_env,
    )
    assert result.returncode == 2
    assert "serial_prot" in result.stderr and result.stderr.count("\n") == 1, result.stderr


def test_a_value_of_the_wrong_type_is_refused():
    with pytest.raises(SettingsFormatError, match="rate_hz"):
        parse({"format_version": FORMAT_VERSION, "rate_hz": "fast"})
