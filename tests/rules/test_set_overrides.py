"""`--set KEY=VALUE` overrides: values per field type, node addressing, errors at `--set:N:1`."""

from pathlib import Path

import pytest

from joshua_codegen.check import check_text
from joshua_codegen.load import load_text
from joshua_codegen.overrides import apply_overrides
from joshua_core.schema import robot_config_pb2 as pb

SEEDS = Path(__file__).parent / "seeds"
FOLLOWER = (SEEDS / "so100_leader_follower.pbtxt").read_text()


def config_after(*overrides):
    result = check_text("r.pbtxt", FOLLOWER, overrides)
    assert [d for d in result.diagnostics if d.path == "--set"] == []
    return result.description.robot_config


def test_robot_fields_blocks_and_env_are_set_by_key():
    config = config_after(
        "mode=MODE_SIMULATION",
        "name=x",
        "shutdown.sigint_grace_s=1",
        "simulation.model=builtin:so100",
        "ros_domain_id=7",
        "env.RMW_IMPLEMENTATION=rmw_fastrtps_cpp",
    )
    assert config.mode == pb.MODE_SIMULATION
    assert config.name == "x"
    assert config.shutdown.sigint_grace_s == 1.0
    assert not config.shutdown.HasField("sigterm_grace_s")
    assert config.simulation.model == "builtin:so100"
    assert config.ros_domain_id == 7
    assert dict(config.env) == {"RMW_IMPLEMENTATION": "rmw_fastrtps_cpp"}


def test_nodes_are_addressed_by_their_derived_or_own_name():
    config = config_after(
        "encoder_publisher.qos_depth=10",
        "actuator_subscriber.device_ids=1, 2,3",
        "data_subscriber.input_topics=/camera/image_raw,/leader/joint_states",
        "camera_publisher.preferred_backend=PYTHON",
        "camera_publisher.critical=false",
        "camera_publisher.rate_hz=12.5",
        "camera_publisher.env.OPENCV_LOG_LEVEL=ERROR",
        "camera_publisher.name=front",
        "front.camera_index=2",
    )
    encoder, actuator, camera, recorder = config.node
    assert encoder.qos_depth == 10
    assert list(actuator.device_ids) == [1, 2, 3]
    assert list(recorder.input_topics) == ["/camera/image_raw", "/leader/joint_states"]
    assert camera.preferred_backend == pb.PYTHON and camera.critical is False and camera.rate_hz == 12.5
    assert camera.name == "front" and camera.camera_index == 2
    assert dict(camera.env) == {"OPENCV_LOG_LEVEL": "ERROR"}


def test_lists_may_be_bracketed_as_in_a_description():
    config = config_after(
        "encoder_publisher.device_ids=[1,2,3]",
        "actuator_subscriber.device_ids=[ 4, 5 ]",
        'data_subscriber.input_topics=["/camera/image_raw", "/leader/joint_states"]',
        'encoder_publisher.joint_names=["a, b", "c", d]',
    )
    encoder, actuator, _camera, recorder = config.node
    assert list(encoder.device_ids) == [1, 2, 3] and list(actuator.device_ids) == [4, 5]
    assert list(recorder.input_topics) == ["/camera/image_raw", "/leader/joint_states"]
    assert list(encoder.joint_names) == ["a, b", "c", "d"]
    assert list(config_after("actuator_subscriber.device_ids=[]").node[1].device_ids) == []


def test_an_empty_value_clears_a_repeated_field():
    assert list(config_after("actuator_subscriber.device_ids=").node[1].device_ids) == []


def test_the_parsed_input_is_never_mutated():
    loaded = load_text("r.pbtxt", FOLLOWER)
    before = loaded.description.SerializeToString(deterministic=True)
    result, _, diagnostics = apply_overrides(loaded.description, loaded.source_map, ["mode=MODE_SIMULATION"])
    assert diagnostics == []
    assert result.robot_config.mode == pb.MODE_SIMULATION
    assert loaded.description.SerializeToString(deterministic=True) == before


@pytest.mark.parametrize(
    ("override", "code", "message"),
    [
        ("mode", "E010", 'expected KEY=VALUE (e.g. mode=MODE_SIMULATION), got "mode"'),
        (".mode=1", "E010", 'key ".mode" has an empty part; expected names joined by "."'),
        (
            "colour=red",
            "E011",
            'no robot field or node named "colour" (nodes: encoder_publisher, '
            "actuator_subscriber, camera_publisher, data_subscriber)",
        ),
        ("camera.qos_depth=3", "E011", 'no robot field or node named "camera"; did you mean "camera_publisher"?'),
        ("encoder_publisher=3", "E011", "name a field of the node: encoder_publisher.FIELD=VALUE"),
        (
            "encoder_publisher.qos_dept=3",
            "E011",
            'node "encoder_publisher" has no field "qos_dept"; did you mean "qos_depth"?',
        ),
        ("shutdown.grace=1", "E011", 'shutdown has no field "grace"'),
        ("env=1", "E011", "set one variable: env.NAME=VALUE"),
        ("node.type=CUSTOM", "E011", "address a node by its name: NODE_NAME.FIELD=VALUE"),
        ("mode=SIMULATION", "E012", 'unknown value "SIMULATION" for mode (enum Mode); did you mean "MODE_SIMULATION"?'),
        ("ros_domain_id=-1", "E012", "ros_domain_id takes an unsigned 32-bit integer (0 to 4294967295), got -1"),
        ("encoder_publisher.device_ids=1,two", "E012", "device_ids takes an unsigned 32-bit integer, got two"),
        ("camera_publisher.critical=maybe", "E012", "critical takes true or false, got maybe"),
        ("encoder_publisher.device_ids=[1,x]", "E012", "device_ids takes an unsigned 32-bit integer, got x"),
        (
            "encoder_publisher.device_ids=[1,2",
            "E012",
            'device_ids: expected "," or "]" in a list, found end of the value',
        ),
        ("encoder_publisher.device_ids=[{}]", "E012", "device_ids takes a list of values: [1, 2, 3] or 1,2,3"),
    ],
)
def test_bad_overrides_are_diagnostics_at_their_position(override, code, message):
    result = check_text("r.pbtxt", FOLLOWER, ["name=ok", override])
    located = [
        (d.path, d.line, d.column, d.end_column, d.code, d.message) for d in result.diagnostics if d.path == "--set"
    ]
    assert located == [("--set", 2, 1, len(override) + 1, code, message)]
    assert result.description.robot_config.name == "ok"


def test_a_failed_override_changes_nothing():
    result = check_text("r.pbtxt", FOLLOWER, ["simulation.nope=1", "encoder_publisher.device_ids=1,x"])
    config = result.description.robot_config
    assert not config.HasField("simulation")
    assert list(config.node[0].device_ids) == [1, 2, 3, 4, 5, 6]


def test_rule_findings_on_an_overridden_value_point_at_the_override():
    result = check_text("r.pbtxt", FOLLOWER, ["mode=MODE_SIMULATION", "actuator_subscriber.qos_depth=0"])
    located = [(d.path, d.line, d.column, d.code) for d in result.diagnostics]
    assert located == [("--set", 1, 1, "E502"), ("--set", 2, 1, "E304"), ("r.pbtxt", 41, 5, "W102")]
    assert result.sources["--set"] == "mode=MODE_SIMULATION\nactuator_subscriber.qos_depth=0"


def test_two_nodes_with_one_name_cannot_be_addressed():
    text = FOLLOWER.replace("type: ENCODER_PUBLISHER", 'name: "arm"\n    type: ENCODER_PUBLISHER')
    text = text.replace("type: ACTUATOR_SUBSCRIBER", 'name: "arm"\n    type: ACTUATOR_SUBSCRIBER')
    result = check_text("r.pbtxt", text, ["arm.qos_depth=1"])
    assert [(d.code, d.message) for d in result.diagnostics if d.path == "--set"] == [
        ("E011", '2 nodes are named "arm"')
    ]


@pytest.mark.process
def test_the_help_says_how_lists_are_written():
    from testsupport.joshuac_cli import joshuac

    help_text = " ".join(joshuac("check", "--help").stdout.split())
    assert "NODE.device_ids=1,2,3 or NODE.device_ids=[1,2,3]" in help_text


def test_hosts_are_addressed_by_their_name():
    text = FOLLOWER.replace(
        "robot_config {",
        'robot_config {\n  host { name: "arm" address: "10.0.0.2" }\n  host { name: "gpu" address: "10.0.0.3" }',
    )
    result = check_text("r.pbtxt", text, ["host.gpu.address=10.0.0.13", "host.arm.ros_from_system=true"])
    assert [d for d in result.diagnostics if d.path == "--set"] == []
    arm, gpu = result.description.robot_config.host
    assert (arm.address, arm.ros_from_system, gpu.address) == ("10.0.0.2", True, "10.0.0.13")


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("host.arm.address=10.0.0.9", 'no host named "arm" (hosts: none)'),
        ("host.arm=10.0.0.9", "address a host by its name: host.NAME.FIELD=VALUE"),
        ("host.arm.adress=1", 'no host named "arm" (hosts: none)'),
    ],
)
def test_a_host_override_names_a_declared_host(override, message):
    result = check_text("r.pbtxt", FOLLOWER, [override])
    assert [(d.code, d.message) for d in result.diagnostics if d.path == "--set"] == [("E011", message)]
