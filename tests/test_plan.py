"""The planner: derived names, endpoint QoS, backend choice and the MODE_SIMULATION substitution."""

import json

from google.protobuf import text_format

from joshua_codegen.emitters.manifest import manifest
from joshua_codegen.emitters.supervisor import supervisor_data
from joshua_codegen.plan import plan
from joshua_codegen.render import Context, render
from joshua_core.schema import RobotDescription
from joshua_core.schema import robot_config_pb2 as pb
from joshua_core.servo_topics import DIAGNOSTICS_TOPIC, preset_topic
from joshua_core.settings import to_literal
from testsupport.joshuac_cli import ROOT


def describe(text: str) -> RobotDescription:
    return text_format.Parse(text, RobotDescription())


def seed(name: str) -> RobotDescription:
    return describe((ROOT / "config" / "robots" / f"{name}.pbtxt").read_text())


def test_unnamed_nodes_get_type_names_numbered_only_when_a_type_repeats():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        node { type: MOCK_CAMERA_PUBLISHER topic_name: "/a" }
        node { type: MOCK_CAMERA_PUBLISHER topic_name: "/b" }
        node { type: MOCK_LIDAR_PUBLISHER topic_name: "/scan" } }"""),
        "r.pbtxt",
    )
    assert [n.name for n in robot.nodes] == [
        "mock_camera_publisher_1",
        "mock_camera_publisher_2",
        "mock_lidar_publisher",
    ]


def test_recorder_inputs_get_a_qos_every_publisher_can_serve():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_DATA_COLLECTION
        node { name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/cam" qos_depth: 3 }
        node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" qos_durability: TRANSIENT_LOCAL }
        node { name: "rec" type: DATA_SUBSCRIBER topic_name: "/joints" input_topics: ["/cam", "/joints"]
               output_directory: "/data" } }"""),
        "r.pbtxt",
    )
    inputs = to_literal(robot.node("rec").settings)["inputs"]
    assert inputs == [
        {
            "name": "/cam",
            "message_type": "sensor_msgs/msg/Image",
            "qos": {"history": "KEEP_LAST", "depth": 3, "reliability": "BEST_EFFORT", "durability": "VOLATILE"},
        },
        {
            "name": "/joints",
            "message_type": "sensor_msgs/msg/JointState",
            "qos": {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"},
        },
    ]


def test_cpp_preference_is_kept_only_for_node_types_that_have_a_cpp_binary():
    robot = plan(seed("so100_leader_follower"), "so100_leader_follower.pbtxt")
    processes = {p.name: p for p in robot.processes}
    assert processes["encoder_publisher"].cpp_binary == "encoder_publisher"
    assert processes["encoder_publisher"].cpp_args[:3] == ("--ros-args", "-r", "__node:=encoder_publisher")
    assert "serial_port:='/dev/ttyUSB0'" in processes["encoder_publisher"].cpp_args
    assert processes["data_subscriber"].cpp_binary == ""


def test_actuator_state_topic_is_a_publisher_in_the_topology():
    robot = plan(seed("mock_arm"), "mock_arm.pbtxt")
    topic = next(t for t in robot.topics if t.name == "/follower/joint_states")
    assert [(e.node, e.message_type) for e in topic.publishers] == [("follower", "sensor_msgs/msg/JointState")]
    assert to_literal(robot.node("follower").settings)["state_topic"]["name"] == "/follower/joint_states"


def test_topics_a_custom_node_declares_reach_the_manifest_and_the_graph():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        node { name: "teleop" type: CUSTOM executable: "/bin/teleop"
               publishes { topic_name: "/arm/commands" message_type: "sensor_msgs/msg/JointState" qos_depth: 3 }
               subscribes { topic_name: "/camera" message_type: "sensor_msgs/msg/Image" qos_reliability: BEST_EFFORT } }
        node { name: "arm" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/arm/commands" }
        node { name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera" } }"""),
        "r.pbtxt",
    )
    document = manifest(robot, Context(prefix="/opt/joshua/r"))
    teleop = next(n for n in document["nodes"] if n["name"] == "teleop")
    assert (teleop["publishes"], teleop["subscribes"]) == (["/arm/commands"], ["/camera"])
    commands = next(t for t in document["topics"] if t["name"] == "/arm/commands")
    assert [(p["node"], p["qos"]["depth"]) for p in commands["publishers"]] == [("teleop", 3)]
    assert commands["message_type"] == "sensor_msgs/msg/JointState"
    camera = next(t for t in document["topics"] if t["name"] == "/camera")
    assert [(s["node"], s["qos"]["reliability"]) for s in camera["subscribers"]] == [("teleop", "BEST_EFFORT")]
    dot = render(robot, "/opt/joshua/r")["topology.dot"]
    assert 'n0 [shape=box, label="teleop\\nCUSTOM\\nPYTHON"];' in dot
    assert 'n0 -> t0 [label="reliable, volatile, depth 3"];' in dot  # t0: /arm/commands
    assert 't1 -> n0 [label="best_effort, volatile, depth 10"];' in dot  # t1: /camera


def test_topics_a_node_type_publishes_by_itself_reach_the_manifest_the_graph_and_its_readers():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        foxglove { port: 8765 }
        node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" }
        node { name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "/joints" }
        node { name: "rec" type: DATA_SUBSCRIBER output_format: "mcap" topic_name: "/joints"
               input_topics: ["/tf", "/tf_static"] output_directory: "/data" } }"""),
        "r.pbtxt",
    )
    document = manifest(robot, Context(prefix="/opt/joshua/r"))
    state = next(n for n in document["nodes"] if n["name"] == "state")
    assert state["publishes"] == ["/tf", "/tf_static", "/robot_description"]
    topics = {t["name"]: t for t in document["topics"]}
    latched = {"history": "KEEP_LAST", "depth": 1, "reliability": "RELIABLE", "durability": "TRANSIENT_LOCAL"}
    for name, message_type, qos in (
        ("/tf", "tf2_msgs/msg/TFMessage", dict(latched, depth=100, durability="VOLATILE")),
        ("/tf_static", "tf2_msgs/msg/TFMessage", latched),
        ("/robot_description", "std_msgs/msg/String", latched),
    ):
        assert topics[name]["message_type"] == message_type
        assert [(p["node"], p["qos"]) for p in topics[name]["publishers"]] == [("state", qos)]
    # The recorder reads them with their publisher's type and a QoS it serves: transient local for /tf_static.
    inputs = {i["name"]: i for i in to_literal(robot.node("rec").settings)["inputs"]}
    assert inputs["/tf"]["message_type"] == "tf2_msgs/msg/TFMessage"
    assert inputs["/tf_static"]["qos"] == latched
    served = {i["name"]: i["qos"]["durability"] for i in to_literal(robot.foxglove)["inputs"]}
    assert served["/tf_static"] == served["/robot_description"] == "TRANSIENT_LOCAL"
    mermaid = render(robot, "/opt/joshua/r")["topology.mmd"]
    assert 't2(["/tf : tf2_msgs/msg/TFMessage"])' in mermaid
    assert (
        'n1 -->|"reliable, volatile, depth 100"| t2' in mermaid
        and 't2 -->|"reliable, volatile, depth 100"| n2' in mermaid
    )
    assert 'n1 -->|"reliable, transient_local, depth 1"| t3' in mermaid  # t3: /tf_static


def test_a_reader_of_a_latched_topic_has_room_for_what_every_publisher_keeps():
    """Two arms' static frames arrive at once when a reader joins: a history of 1 would drop one of them."""
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        node { name: "left" type: MOCK_ENCODER_PUBLISHER topic_name: "/left/joints" }
        node { name: "right" type: MOCK_ENCODER_PUBLISHER topic_name: "/right/joints" }
        node { name: "left_state" type: ROBOT_STATE_PUBLISHER topic_name: "/left/joints" }
        node { name: "right_state" type: ROBOT_STATE_PUBLISHER topic_name: "/right/joints" }
        node { name: "rec" type: DATA_SUBSCRIBER output_format: "mcap" topic_name: "/left/joints"
               input_topics: ["/tf_static", "/tf"] output_directory: "/data" } }"""),
        "r.pbtxt",
    )
    inputs = {i["name"]: i["qos"] for i in to_literal(robot.node("rec").settings)["inputs"]}
    assert (inputs["/tf_static"]["durability"], inputs["/tf_static"]["depth"]) == ("TRANSIENT_LOCAL", 2)
    assert (inputs["/tf"]["durability"], inputs["/tf"]["depth"]) == ("VOLATILE", 100)  # the deepest, as before


def _endpoints(document: dict) -> list:
    return [
        (
            t["name"],
            t["message_type"],
            sorted((p["node"], json.dumps(p["qos"], sort_keys=True)) for p in t["publishers"]),
            sorted((s["node"], json.dumps(s["qos"], sort_keys=True)) for s in t["subscribers"]),
        )
        for t in document["topics"]
    ]


def test_simulation_replaces_hardware_nodes_by_one_engine_on_the_same_topics_types_and_qos():
    real_description = seed("so100_leader_follower")
    simulated_description = RobotDescription()
    simulated_description.CopyFrom(real_description)
    simulated_description.robot_config.mode = pb.MODE_SIMULATION
    simulated_description.robot_config.simulation.model = "builtin:so100"
    context = Context(prefix="/opt/joshua/x")
    real = manifest(plan(real_description, "a.pbtxt"), context)
    simulated = manifest(plan(simulated_description, "a.pbtxt"), context)
    assert _endpoints(simulated) == _endpoints(real)
    assert {DIAGNOSTICS_TOPIC, preset_topic("/leader/joint_states")} <= {e[0] for e in _endpoints(real)}
    assert [p["name"] for p in simulated["processes"]] == ["data_subscriber", "simulation"]
    engine = simulated["processes"][1]
    assert engine["simulates"] == ["encoder_publisher", "actuator_subscriber", "camera_publisher"]
    assert {n["name"]: n["simulated_by"] for n in simulated["nodes"]} == {
        "encoder_publisher": "simulation",
        "actuator_subscriber": "simulation",
        "camera_publisher": "simulation",
        "data_subscriber": None,
    }
    files = render(plan(simulated_description, "a.pbtxt"), "/opt/joshua/x")
    assert "nodes/simulation.py" in files and "nodes/camera_publisher.py" not in files
    assert "simulated by simulation" in files["topology.dot"]
    assert "'simulates': [" in files["nodes/simulation.py"]


def test_relative_and_private_topic_names_resolve_to_one_topic():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "joints" }
        node { name: "follow" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/joints" state_topic: "~/state" } }"""),
        "r.pbtxt",
    )
    assert [(t.name, [e.node for e in t.publishers], [e.node for e in t.subscribers]) for t in robot.topics] == [
        ("/follow/state", ["follow"], []),
        ("/joints", ["arm"], ["follow"]),
    ]
    assert to_literal(robot.node("follow").settings)["state_topic"]["name"] == "/follow/state"


def test_a_simulated_robot_needs_none_of_the_devices_of_the_nodes_it_simulates():
    description = seed("so100_sim")
    document = manifest(plan(description, "so100_sim.pbtxt"), Context(prefix="/opt/joshua/so100_sim"))
    assert document["devices"] == []
    follower = next(node for node in document["nodes"] if node["name"] == "follower")
    assert follower["devices"] == [{"kind": "serial", "path": "/dev/ttyUSB0"}]


def test_only_processes_that_carry_images_get_the_image_transport_profile():
    description = describe("""robot_config { name: "r" mode: MODE_DATA_COLLECTION
        node { name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/image" message_type: "sensor_msgs/msg/CompressedImage" }
        node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" }
        node { name: "rec" type: DATA_SUBSCRIBER topic_name: "/joints" input_topics: ["/image"] output_directory: "/d" }
        node { name: "follow" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/joints" }
        node { name: "own" type: CUSTOM executable: "/bin/true" } }""")
    robot = plan(description, "r.pbtxt")
    assert {p.name: p.carries_images for p in robot.processes} == {
        "cam": True,
        "arm": False,
        "rec": True,
        "follow": False,
        "own": True,
    }  # a custom process may carry anything
    files = render(robot, "/opt/r")
    images, plain = "/opt/r/fastdds_profile_images.xml", "/opt/r/fastdds_profile.xml"
    for name, profile in (("cam", images), ("arm", plain), ("rec", images), ("own", images)):
        assert f"FASTRTPS_DEFAULT_PROFILES_FILE={profile}\n" in files[f"systemd/joshua-r-{name}.service"]
        program = files["supervisord.conf"].split(f"[program:{name}]\n")[1].split("[program:")[0]
        assert f'FASTRTPS_DEFAULT_PROFILES_FILE="{profile.replace("/opt/r", "%(here)s")}",' in program
    assert (
        "<segment_size>" in files["fastdds_profile_images.xml"] and "<segment_size>" not in files["fastdds_profile.xml"]
    )


def test_the_simulation_engine_carries_images_only_when_it_simulates_a_camera():
    def engine(nodes: str) -> bool:
        robot = plan(
            describe(f"""robot_config {{ name: "r" mode: MODE_SIMULATION simulation {{ model: "builtin:so100" }}
            {nodes} }}"""),
            "r.pbtxt",
        )
        return next(p for p in robot.processes if p.node_type == "SIMULATION").carries_images

    arm = 'node { type: ENCODER_PUBLISHER topic_name: "/joints" serial_port: "/dev/ttyUSB0" }'
    assert engine(arm + ' node { type: CAMERA_PUBLISHER topic_name: "/image" }') is True
    assert engine(arm) is False


def test_supervisor_data_names_each_process_its_own_dds_profile():
    robot = plan(
        describe("""robot_config { name: "r" mode: MODE_TELEOPERATION
        node { name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "/image" }
        node { name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" } }"""),
        "r.pbtxt",
    )
    profiles = {p["name"]: p["fastdds_profile"] for p in supervisor_data(robot)["processes"]}
    assert profiles == {"cam": "fastdds_profile_images.xml", "arm": "fastdds_profile.xml"}


def test_the_simulated_lego_car_serves_the_real_base_topics_types_and_qos():
    real_description = seed("lego_bot")
    simulated_description = RobotDescription()
    simulated_description.CopyFrom(real_description)
    simulated_description.robot_config.mode = pb.MODE_SIMULATION
    context = Context(prefix="/opt/joshua/lego_bot")
    real = manifest(plan(real_description, "lego_bot.pbtxt"), context)
    simulated = manifest(plan(simulated_description, "lego_bot.pbtxt"), context)
    assert _endpoints(simulated) == _endpoints(real)
    assert [(t["name"], t["message_type"]) for t in real["topics"]] == [
        ("/cmd_vel", "geometry_msgs/msg/Twist"),
        ("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray"),  # the hub link's status
        ("/odom", "nav_msgs/msg/Odometry"),
        ("/tf", "tf2_msgs/msg/TFMessage"),  # odom -> base_link, broadcast by every base
        ("/wheel_states", "sensor_msgs/msg/JointState"),
    ]
    assert [p["name"] for p in simulated["processes"]] == ["simulation"]
    assert simulated["processes"][0]["simulates"] == ["base"]
