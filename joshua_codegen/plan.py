"""Turn a checked RobotDescription into the frozen Robot model (pure; no I/O)."""

import os

from joshua_codegen import defaults, escape, topology
from joshua_codegen.model import Device, Endpoint, NodeModel, Process, QoS, Robot, Topic
from joshua_core.models import GL_BACKENDS, REGISTRY_PREFIX
from joshua_core.node_types import NODE_TYPES, SIMULATION_ENGINE
from joshua_core.schema import robot_config_pb2 as pb


# Value of a setting whose field does not apply to the node type ("" / [] / 0 unless named here).
_NOT_APPLICABLE = {"camera_index": -1}


def plan(description: pb.RobotDescription, source: str) -> Robot:
    """Build the model of a description the rules accepted. `source` is the description's path."""
    config = description.robot_config
    mode = pb.Mode.Name(config.mode)
    names = defaults.node_names(config)
    simulating = config.mode == pb.MODE_SIMULATION
    hardware = any(node.type in defaults.HARDWARE for node in config.node)
    engine = defaults.SIMULATION_NAME if simulating and hardware else ""  # a reserved name there (E205)
    declared = topology.declarations(config, names)
    publishers = _publishers(declared)
    nodes = tuple(
        _node(config, node, name, index, [d for d in declared if d.index == index], publishers,
              engine if node.type in defaults.HARDWARE else "")
        for index, (node, name) in enumerate(zip(config.node, names))
    )
    processes = tuple(_process(config, node, model) for node, model in zip(config.node, nodes) if not model.simulated_by)
    simulation = None
    if engine:
        simulated = [model for model in nodes if model.simulated_by]
        simulation = _simulation(config, simulated)
        processes += (_engine_process(engine, simulated),)
    return Robot(
        name=config.name,
        mode=mode,
        source=os.path.basename(source),
        nodes=nodes,
        topics=_topics(nodes),
        processes=processes,
        sigint_grace_s=_grace(config.shutdown, "sigint_grace_s", defaults.SIGINT_GRACE_S),
        sigterm_grace_s=_grace(config.shutdown, "sigterm_grace_s", defaults.SIGTERM_GRACE_S),
        ros_domain_id=config.ros_domain_id if config.HasField("ros_domain_id") else None,
        cpp_bin_dir=config.cpp_bin_dir or defaults.CPP_BIN_DIR,
        python_executable=config.python_executable or defaults.PYTHON_EXECUTABLE,
        env=tuple(sorted(config.env.items())),
        simulation=simulation,
    )


def _grace(shutdown: pb.Shutdown, field: str, default: float) -> float:
    return getattr(shutdown, field) if shutdown.HasField(field) else default


def _endpoint(declared: topology.Declaration, message_type: str, qos: QoS) -> Endpoint:
    role = "publisher" if declared.role == topology.PUBLISHER else "subscriber"
    return Endpoint(declared.node, declared.topic, message_type, qos, role)


def _publishers(declared: list[topology.Declaration]) -> dict[str, list[Endpoint]]:
    """Every publisher of the description, by topic name."""
    by_topic: dict[str, list[Endpoint]] = {}
    for item in declared:
        if item.role == topology.PUBLISHER:
            by_topic.setdefault(item.topic, []).append(_endpoint(item, item.message_type, QoS(**item.qos)))
    return by_topic


def _matching_qos(publishers: list[Endpoint]) -> QoS:
    """A subscription QoS every publisher of a topic can serve, with the deepest publisher history."""
    if not publishers:  # published outside the description: best effort, volatile accepts any publisher
        return QoS("KEEP_LAST", 10, "BEST_EFFORT", "VOLATILE")
    reliable = all(p.qos.reliability == "RELIABLE" for p in publishers)
    durable = all(p.qos.durability == "TRANSIENT_LOCAL" for p in publishers)
    depth = max(p.qos.depth for p in publishers) or 10
    return QoS("KEEP_LAST", depth, "RELIABLE" if reliable else "BEST_EFFORT",
               "TRANSIENT_LOCAL" if durable else "VOLATILE")


def _node(config: pb.RobotConfig, node: pb.Node, name: str, index: int, declared: list[topology.Declaration],
          publishers: dict[str, list[Endpoint]], simulated_by: str) -> NodeModel:
    published, main, inputs, fields = [], [], [], {}
    for item in declared:
        if item.role == topology.READER:
            if any(e.topic == item.topic for e in inputs):
                continue  # read once however often it is listed
            found = publishers.get(item.topic, [])
            endpoint = _endpoint(item, found[0].message_type if found else "", _matching_qos(found))
            inputs.append(endpoint)
            continue
        endpoint = _endpoint(item, item.message_type, QoS(**item.qos))
        (published if item.role == topology.PUBLISHER else main).append(endpoint)
        fields[item.at[-1]] = endpoint
    topic, state = fields.get("topic_name"), fields.get("state_topic")
    devices = tuple(_devices(node, name))
    settings = {
        "robot": config.name,
        "mode": pb.Mode.Name(config.mode),
        "name": name,
        "type": defaults.type_name(node.type),
        "topic": topic.as_topic_settings() if topic else None,
        "state_topic": state.as_topic_settings() if state else None,
        "inputs": [e.as_topic_settings() for e in inputs],
        "qos": defaults.qos(node),
        "serial_port": node.serial_port,
        "baud_rate": defaults.baud_rate(node),
        "device_ids": defaults.device_ids(node),
        "joint_names": defaults.joint_names(node) if defaults.device_ids(node) or node.joint_names else [],
        "calibration_file": node.calibration_file,
        "keep_torque_on_exit": node.keep_torque_on_exit,
        "camera_index": node.camera_index if node.HasField("camera_index") else (0 if node.type in defaults.CAMERAS else -1),
        "video_source": node.video_source,
        "width": node.width if node.HasField("width") else 640,
        "height": node.height if node.HasField("height") else 480,
        "rate_hz": defaults.rate_hz(node),
        "frame_id": defaults.frame_id(node),
        "model_path": node.model_path,
        "policy_type": node.policy_type,
        "device": node.device or "cpu",
        "output_format": node.output_format or "lerobot",
        "output_directory": node.output_directory,
        "simulation": None,
    }
    for key in settings.keys() & defaults.FIELD_APPLIES_TO.keys():
        if node.type not in defaults.FIELD_APPLIES_TO[key]:
            settings[key] = _NOT_APPLICABLE.get(key, type(settings[key])())
    return NodeModel(
        name=name,
        type=defaults.type_name(node.type),
        index=index,
        backend=defaults.backend(node),
        simulated_by=simulated_by,
        publishes=tuple(published),
        subscribes=tuple(main + inputs),
        devices=devices,
        settings=settings,
    )


def _devices(node: pb.Node, name: str):
    """What the node's registry entry claims, as the devices that must be present before start."""
    claims = defaults.entry(node).claims
    if "serial_port" in claims and node.serial_port:
        yield Device("serial", node.serial_port, name)
    if "video_file" in claims and node.video_source and "://" not in node.video_source:
        yield Device("file", node.video_source, name)
    if "camera" in claims and not node.video_source:
        index = node.camera_index if node.HasField("camera_index") else 0
        yield Device("camera", f"/dev/video{index}", name)
    if "model_path" in claims and node.model_path and not node.model_path.startswith(REGISTRY_PREFIX):
        yield Device("model", node.model_path, name)


def _process(config: pb.RobotConfig, node: pb.Node, model: NodeModel) -> Process:
    custom = node.type == pb.CUSTOM
    env = dict(config.env)
    env.update(node.env)
    return Process(
        name=model.name,
        node_type=model.type,
        kind="custom" if custom else "python",
        entrypoint="" if custom else f"nodes/{model.name}.py",
        executable=node.executable,
        args=tuple(node.args),
        cpp_binary=model.type.lower() if model.backend == "CPP" else "",
        cpp_args=_cpp_args(model) if model.backend == "CPP" else (),
        restart=defaults.restart(node),
        max_restarts=defaults.max_restarts(node),
        critical=defaults.critical(node),
        env=tuple(sorted(env.items())),
        devices=model.devices,
    )


def _cpp_args(model: NodeModel) -> tuple[str, ...]:
    """`--ros-args -r __node:=NAME -p field:=value ...` for the C++ binary of a node."""
    settings = model.settings
    topic = settings["topic"] or {}
    qos = settings["qos"]
    values = dict(settings)
    values.update({
        "topic_name": topic.get("name", ""),
        "message_type": topic.get("message_type", ""),
        "qos_depth": qos["depth"],
        "qos_reliability": qos["reliability"],
        "qos_durability": qos["durability"],
        "qos_history": qos["history"],
        "state_topic": (settings["state_topic"] or {}).get("name", ""),
    })
    args = ["--ros-args", "-r", f"__node:={model.name}"]
    for key in NODE_TYPES[model.type].cpp_parameters:
        if values[key] in ("", [], -1):
            continue
        args += ["-p", f"{key}:={escape.ros_parameter(values[key])}"]
    return tuple(args)


def _simulation(config: pb.RobotConfig, simulated: list[NodeModel]) -> dict:
    sim = config.simulation
    return {
        "model": sim.model,
        "timestep_s": sim.timestep_s if sim.HasField("timestep_s") else None,
        "realtime_factor": sim.realtime_factor if sim.HasField("realtime_factor") else 1.0,
        "camera": sim.camera,
        "gl_backend": sim.gl_backend or GL_BACKENDS[0],
        "simulates": [model.settings for model in simulated],
    }


def _engine_process(name: str, simulated: list[NodeModel]) -> Process:
    return Process(
        name=name, node_type=SIMULATION_ENGINE.name, kind="python", entrypoint=f"nodes/{name}.py", executable="",
        args=(), cpp_binary="", cpp_args=(), restart="RESTART_ON_FAILURE", max_restarts=defaults.MAX_RESTARTS,
        critical=True, env=(), devices=(),
    )


def _topics(nodes: tuple[NodeModel, ...]) -> tuple[Topic, ...]:
    publishers: dict[str, list[Endpoint]] = {}
    subscribers: dict[str, list[Endpoint]] = {}
    for node in nodes:
        for endpoint in node.publishes:
            publishers.setdefault(endpoint.topic, []).append(endpoint)
        for endpoint in node.subscribes:
            subscribers.setdefault(endpoint.topic, []).append(endpoint)
    topics = []
    for name in sorted(set(publishers) | set(subscribers)):
        pubs, subs = publishers.get(name, []), subscribers.get(name, [])
        message_type = (pubs or subs)[0].message_type
        topics.append(Topic(name, message_type, tuple(pubs), tuple(subs)))
    return tuple(topics)
