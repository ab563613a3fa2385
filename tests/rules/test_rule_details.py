"""Rule behaviour the fixtures do not show: exemptions, topic resolution, defaults, many endpoints."""

from joshua_codegen.check import check_text


def codes(text: str, overrides=()) -> list[tuple[str, int, int]]:
    return [(d.code, d.line, d.column) for d in check_text("r.pbtxt", text, overrides).diagnostics]


def robot(*nodes: str, mode: str = "MODE_TELEOPERATION", extra: str = "") -> str:
    body = "".join(f"  node {{ {node} }}\n" for node in nodes)
    return f'robot_config {{\n  name: "r"\n  mode: {mode}\n{extra}{body}}}\n'


def test_serial_ports_are_not_required_in_simulation():
    text = robot(
        'type: ENCODER_PUBLISHER topic_name: "/a"',
        'type: ACTUATOR_SUBSCRIBER topic_name: "/a"',
        mode="MODE_SIMULATION",
        extra='  simulation { model: "builtin:so100" }\n',
    )
    assert codes(text) == []
    assert codes(text, ["mode=MODE_TELEOPERATION"]) == [("E105", 5, 3), ("E105", 6, 3)]


def test_relative_absolute_and_private_names_of_one_topic_match():
    text = robot(
        'name: "enc" type: MOCK_ENCODER_PUBLISHER topic_name: "arm/state"',
        'type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/arm/state" state_topic: "~/out"',
        'type: DATA_SUBSCRIBER topic_name: "/mock_actuator_subscriber/out" output_directory: "/d" '
        'input_topics: ["arm/state"]',
        mode="MODE_DATA_COLLECTION",
    )
    assert codes(text) == []


def test_a_recorder_topic_is_the_joint_state_action_and_other_types_are_reported():
    arm = 'type: MOCK_ENCODER_PUBLISHER topic_name: "/j"'
    untyped = 'type: DATA_SUBSCRIBER topic_name: "/j" output_directory: "/d" input_topics: "/j"'
    assert codes(robot(arm, untyped)) == []
    camera = 'type: MOCK_CAMERA_PUBLISHER topic_name: "/j"'
    assert codes(
        robot(camera, untyped.replace('topic_name: "/j"', 'topic_name: "/j" qos_reliability: BEST_EFFORT'))
    ) == [("E207", 5, 32)]
    typed = untyped.replace("type: DATA_SUBSCRIBER", 'type: DATA_SUBSCRIBER message_type: "std_msgs/msg/String"')
    assert codes(robot(arm, typed)) == [("E202", 5, 32), ("E207", 5, 32)]


def test_a_custom_node_topic_name_is_ignored_with_a_warning_naming_the_declaration_blocks():
    text = robot(
        'type: CUSTOM executable: "/bin/tool" topic_name: "/a"', 'type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/a"'
    )
    result = check_text("r.pbtxt", text)
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [("W101", 4, 47), ("W202", 5, 41)]
    assert "publishes { topic_name: ... message_type: ... }" in result.diagnostics[0].message


def test_topics_a_custom_node_declares_take_part_in_type_and_qos_checks():
    teleop = (
        'name: "teleop" type: CUSTOM executable: "/bin/teleop" '
        'publishes { topic_name: "/arm/commands" message_type: "sensor_msgs/msg/JointState" '
        "qos_reliability: BEST_EFFORT } "
        'subscribes { topic_name: "/camera" message_type: "sensor_msgs/msg/JointState" qos_depth: 0 }'
    )
    arm = 'type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/arm/commands"'
    camera = 'type: MOCK_CAMERA_PUBLISHER topic_name: "/camera"'
    result = check_text("r.pbtxt", robot(teleop, arm, camera))
    # The subscription: E301 (the camera offers BEST_EFFORT), E207 at its message_type, E304 at its
    # qos_depth; the arm: E301, with the note at the declaration's qos_reliability.
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [
        ("E301", 4, 191),
        ("E207", 4, 213),
        ("E304", 4, 256),
        ("E301", 5, 41),
    ]
    assert [(r.line, r.column) for r in result.diagnostics[3].related] == [(4, 147)]


def test_a_custom_subscription_counts_as_a_subscriber_of_a_published_topic():
    teleop = (
        'type: CUSTOM executable: "/bin/t" subscribes { topic_name: "/cam" '
        'message_type: "sensor_msgs/msg/Image" qos_reliability: BEST_EFFORT }'
    )
    assert codes(robot(teleop, 'type: MOCK_CAMERA_PUBLISHER topic_name: "/cam"')) == []
    assert codes(robot(teleop)) == [("W202", 4, 57)]


def test_one_finding_per_subscriber_however_many_publishers():
    publishers = [
        f'name: "p{i}" type: MOCK_ENCODER_PUBLISHER topic_name: "/c" qos_reliability: BEST_EFFORT' for i in range(300)
    ]
    subscriber = 'type: DATA_SUBSCRIBER topic_name: "/c" output_directory: "/d" input_topics: "/c"'
    result = check_text("r.pbtxt", robot(*publishers, subscriber))
    assert [d.code for d in result.diagnostics] == ["E301"]
    assert result.diagnostics[0].message == (
        'publisher "p0" (and 299 more) offers BEST_EFFORT, subscriber "data_subscriber" requires RELIABLE on "/c"'
    )


def test_best_effort_subscription_of_a_reliable_publisher_is_fine():
    text = robot(
        'type: MOCK_ENCODER_PUBLISHER topic_name: "/a" qos_durability: TRANSIENT_LOCAL',
        'type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/a" qos_reliability: BEST_EFFORT',
    )
    assert codes(text) == []


def test_nodes_without_a_type_are_left_to_e103():
    assert codes(robot('name: "x"')) == [("E103", 4, 3)]


def test_a_bag_recorder_records_inputs_of_any_type():
    lidar = 'type: MOCK_LIDAR_PUBLISHER topic_name: "/scan"'
    arm = 'type: MOCK_ENCODER_PUBLISHER topic_name: "/j"'
    recorder = 'type: DATA_SUBSCRIBER topic_name: "/j" output_directory: "/d" input_topics: ["/scan"]'
    assert codes(robot(lidar, arm, recorder, mode="MODE_DATA_COLLECTION")) == [("E208", 6, 87)]
    bag = recorder + ' output_format: "mcap" bag_max_size_mb: 100 bag_max_duration_s: 60'
    assert codes(robot(lidar, arm, bag, mode="MODE_DATA_COLLECTION")) == []


TRAJECTORY = 'message_type: "trajectory_msgs/msg/JointTrajectory"'
CHUNK_POLICY = f'type: INFERENCE topic_name: "/arm/commands" {TRAJECTORY} model_path: "/m" input_topics: ["/cam"]'
CAMERA = 'type: MOCK_CAMERA_PUBLISHER topic_name: "/cam"'


def test_action_chunks_flow_from_inference_to_actuators_and_the_simulation():
    for actuator in ('ACTUATOR_SUBSCRIBER serial_port: "/dev/ttyACM0"', "MOCK_ACTUATOR_SUBSCRIBER"):
        follower = f'type: {actuator} topic_name: "/arm/commands" {TRAJECTORY}'
        assert codes(robot(CAMERA, CHUNK_POLICY, follower, mode="MODE_INFERENCE")) == []
    simulated = robot(
        'type: CAMERA_PUBLISHER topic_name: "/cam"',
        CHUNK_POLICY,
        f'type: ACTUATOR_SUBSCRIBER topic_name: "/arm/commands" {TRAJECTORY}',
        mode="MODE_SIMULATION",
        extra='  simulation { model: "builtin:so100" }\n',
    )
    assert codes(simulated) == []


def test_a_joint_state_subscriber_of_a_trajectory_topic_is_a_type_mismatch():
    follower = 'type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/arm/commands"'
    assert codes(robot(CAMERA, CHUNK_POLICY, follower, mode="MODE_INFERENCE")) == [("E207", 6, 41)]
    typed = follower + ' message_type: "sensor_msgs/msg/JointState"'
    assert codes(robot(CAMERA, CHUNK_POLICY, typed, mode="MODE_INFERENCE")) == [("E207", 6, 69)]
    recorder = 'type: DATA_SUBSCRIBER topic_name: "/arm/commands" output_directory: "/d" input_topics: ["/cam"]'
    assert [code for code, _, _ in codes(robot(CAMERA, CHUNK_POLICY, recorder, mode="MODE_INFERENCE"))] == ["E207"]
