"""Each process's NodeSettings message (the settings contract, proto/joshua/v1/node_settings.proto),
built from a checked description with every default resolved (pure; no I/O)."""

from joshua_codegen import defaults
from joshua_codegen.model import Endpoint
from joshua_core.models import DEFAULT_ROBOT_DESCRIPTION
from joshua_core.node_types import FOXGLOVE_BRIDGE, SIMULATION_ENGINE
from joshua_core.schema import robot_config_pb2 as pb
from joshua_core.settings import (
    FORMAT_VERSION,
    NodeSettings,
    PresetSettings,
    QosSettings,
    SimulationSettings,
    TopicSettings,
)


def _topic(endpoint: Endpoint) -> TopicSettings:
    return TopicSettings(
        name=endpoint.topic, message_type=endpoint.message_type, qos=QosSettings(**endpoint.qos.as_dict())
    )


def _common(config: pb.RobotConfig, name: str, type_name: str) -> NodeSettings:
    return NodeSettings(
        format_version=FORMAT_VERSION, robot=config.name, mode=pb.Mode.Name(config.mode), name=name, type=type_name
    )


def for_node(
    config: pb.RobotConfig,
    node: pb.Node,
    name: str,
    topic: Endpoint | None,
    state: Endpoint | None,
    inputs: list[Endpoint],
    odom: Endpoint | None = None,
    compressed: Endpoint | None = None,
) -> NodeSettings:
    """The settings of one described node; fields its type does not read are left at their zero value."""
    settings = _common(config, name, defaults.type_name(node.type))
    if topic is not None:
        settings.topic.CopyFrom(_topic(topic))
    if state is not None:
        settings.state_topic.CopyFrom(_topic(state))
    if odom is not None:
        settings.odom_topic.CopyFrom(_topic(odom))
    if compressed is not None:
        settings.compressed_topic.CopyFrom(_topic(compressed))
    settings.inputs.extend(_topic(endpoint) for endpoint in inputs)
    settings.qos.CopyFrom(QosSettings(**defaults.qos(node)))
    ids = defaults.device_ids(node)
    applicable = {
        "serial_port": node.serial_port,
        "baud_rate": defaults.baud_rate(node),
        "device_ids": ids,
        "joint_names": defaults.joint_names(node) if ids or node.joint_names or node.type in defaults.BASES else [],
        "calibration_file": node.calibration_file,
        "keep_torque_on_exit": node.keep_torque_on_exit,
        "on_command_timeout": defaults.on_command_timeout(node),
        "preset": [PresetSettings(name=p.name, positions={j.name: j.position for j in p.joint}) for p in node.preset],
        "diagnostics_rate_hz": defaults.diagnostics_rate_hz(node),
        "camera_index": defaults.camera_index(node),
        "video_source": node.video_source,
        "width": defaults.width(node),
        "height": defaults.height(node),
        "rate_hz": defaults.rate_hz(node),
        "frame_id": defaults.frame_id(node),
        "model_path": node.model_path,
        "policy_type": node.policy_type,
        "device": defaults.device(node),
        "output_format": defaults.output_format(node),
        "output_directory": node.output_directory,
        "wheel_radius_m": defaults.wheel_radius_m(node),
        "track_width_m": defaults.track_width_m(node),
        "hub": defaults.hub(node),
        "command_timeout_s": defaults.command_timeout_s(node),
        "ble_transport": node.ble_transport,
        "bag_max_size_mb": node.bag_max_size_mb,
        "bag_max_duration_s": node.bag_max_duration_s,
        "units": defaults.units(node),
        "episode_time_s": node.episode_time_s,
        "reset_time_s": node.reset_time_s,
        "robot_description": node.robot_description or DEFAULT_ROBOT_DESCRIPTION,
    }
    for key, value in applicable.items():
        if key in defaults.FIELD_APPLIES_TO and node.type not in defaults.FIELD_APPLIES_TO[key]:
            continue  # left at its zero value, as the contract says
        if isinstance(value, list):
            getattr(settings, key).extend(value)
        else:
            setattr(settings, key, value)
    return settings


def for_simulation(config: pb.RobotConfig, simulates: list[NodeSettings]) -> SimulationSettings:
    """The simulation engine's section: the world, and the settings of every node it stands in for."""
    sim = config.simulation
    section = SimulationSettings(
        model=sim.model,
        realtime_factor=defaults.realtime_factor(sim),
        camera=sim.camera,
        gl_backend=defaults.gl_backend(sim),
    )
    if sim.HasField("timestep_s"):
        section.timestep_s = sim.timestep_s
    section.simulates.extend(simulates)
    return section


def for_foxglove(config: pb.RobotConfig, name: str, topics: list[Endpoint]) -> NodeSettings:
    """The settings of the Foxglove bridge process: where it listens and the topics it serves."""
    settings = _common(config, name, FOXGLOVE_BRIDGE.name)
    foxglove = config.foxglove
    settings.foxglove.port = foxglove.port if foxglove.HasField("port") else defaults.FOXGLOVE_PORT
    settings.foxglove.host = foxglove.bind or defaults.FOXGLOVE_BIND
    settings.inputs.extend(_topic(endpoint) for endpoint in topics)
    return settings


def for_engine(config: pb.RobotConfig, name: str, simulation: SimulationSettings) -> NodeSettings:
    """The settings of the simulation engine process of MODE_SIMULATION."""
    settings = _common(config, name, SIMULATION_ENGINE.name)
    settings.simulation.CopyFrom(simulation)
    return settings
