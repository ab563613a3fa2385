"""Turn a checked RobotDescription into the frozen Robot model (pure; no I/O)."""

import json
import os
from dataclasses import replace

from joshua_codegen import defaults, escape, image_transport, node_settings, placement, service_processes, topology
from joshua_codegen.model import (
    Device,
    DiscoveryServer,
    Endpoint,
    Host,
    NodeModel,
    Process,
    QoS,
    Robot,
    Topic,
)
from joshua_codegen.positions import node_path
from joshua_core import dashboard as dashboard_facts
from joshua_core.message_types import IMAGE_TYPES
from joshua_core.models import BUILTIN_PREFIX, REGISTRY_PREFIX
from joshua_core.node_families import Family
from joshua_core.node_types import NODE_TYPES
from joshua_core.schema import robot_config_pb2 as pb

SUBSCRIBE_DEPTH = 10  # history of a subscription whose publishers state none (or are outside the description)


def plan(description: pb.RobotDescription, source: str) -> Robot:
    """Build the model of a description the rules accepted. `source` is the description's path."""
    config = description.robot_config
    mode = pb.Mode.Name(config.mode)
    names = defaults.node_names(config)
    simulating = config.mode == pb.MODE_SIMULATION
    hardware = any(node.type in defaults.HARDWARE for node in config.node)
    engine = defaults.SIMULATION_NAME if simulating and hardware else ""  # a reserved name there (E205)
    declared = image_transport.across_hosts(config, topology.declarations(config, names))
    publishers = _publishers(declared)
    by_node: dict[int, list[topology.Declaration]] = {}
    for item in declared:
        by_node.setdefault(item.index, []).append(item)
    nodes = tuple(
        _node(
            config,
            node,
            name,
            index,
            by_node.get(index, []),
            publishers,
            engine if node.type in defaults.HARDWARE else "",
        )
        for index, (node, name) in enumerate(zip(config.node, names))
    )
    written = _written_files(config, nodes)
    processes = tuple(
        _process(config, node, model, written) for node, model in zip(config.node, nodes) if not model.simulated_by
    )
    simulation = None
    if engine:
        simulated = [model for model in nodes if model.simulated_by]
        section = node_settings.for_simulation(config, [model.settings for model in simulated])
        simulation = node_settings.for_engine(config, engine, section)
        model_file = _file_named(section.model)
        processes += (
            service_processes.engine_process(engine, any(_carries_images(model) for model in simulated), model_file),
        )
    topics = _topics(nodes)
    foxglove = _foxglove_settings(config, topics) if config.HasField("foxglove") else None
    if foxglove is not None:
        processes += (
            service_processes.foxglove_process(foxglove.name, any(t.message_type in IMAGE_TYPES for t in topics)),
        )
    if config.HasField("dashboard"):
        processes += (service_processes.dashboard_process(config, any(_carries_images(model) for model in nodes)),)
    hosts, discovery, control = (), None, None
    if placement.has_hosts(config):
        hosts, discovery, processes = _placed(config, processes)
        control = service_processes.control_router(config, hosts)
    return Robot(
        name=config.name,
        mode=mode,
        source=os.path.basename(source),
        nodes=nodes,
        topics=topics,
        processes=processes,
        sigint_grace_s=_grace(config.shutdown, "sigint_grace_s", defaults.SIGINT_GRACE_S),
        sigterm_grace_s=_grace(config.shutdown, "sigterm_grace_s", defaults.SIGTERM_GRACE_S),
        ros_domain_id=config.ros_domain_id if config.HasField("ros_domain_id") else None,
        cpp_bin_dir=config.cpp_bin_dir or defaults.CPP_BIN_DIR,
        python_executable=config.python_executable or defaults.PYTHON_EXECUTABLE,
        env=tuple(sorted(config.env.items())),
        simulation=simulation,
        foxglove=foxglove,
        hosts=hosts,
        discovery=discovery,
        control=control,
        placement={process.name: process.host for process in processes} if hosts else {},
    )


def _placed(config: pb.RobotConfig, processes: tuple[Process, ...]):
    """(hosts, Discovery Server, processes each with its host, the server's first) of a robot on several hosts."""
    hosts = tuple(Host(h.name, h.address, h.ros_from_system, placement.host_python(h)) for h in config.host)
    services = {
        defaults.SIMULATION_NAME: "simulation",
        defaults.FOXGLOVE_NAME: "foxglove",
        dashboard_facts.PROCESS_NAME: "dashboard",
    }
    nodes = {name: node for node, name in zip(config.node, defaults.node_names(config))}
    placed = []
    for process in processes:
        if process.name in nodes:
            host = placement.node_host(config, nodes[process.name])
        else:
            host = placement.service_host(config, services[process.name])
        placed.append(replace(process, host=host))
    discovery = None
    if config.HasField("discovery"):
        server = next(h for h in hosts if h.name == config.discovery.server_host)
        discovery = DiscoveryServer(server.name, server.address, placement.discovery_port(config))
        placed.insert(0, service_processes.discovery_process(discovery))
    placed += [service_processes.host_agent_process(config, host, hosts) for host in hosts]
    return hosts, discovery, tuple(placed)


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
    """A subscription QoS every publisher of a topic can serve, with the deepest publisher history; when
    all of them keep messages for late subscribers, room for what every one of them keeps."""
    if not publishers:  # published outside the description: best effort, volatile accepts any publisher
        return QoS("KEEP_LAST", SUBSCRIBE_DEPTH, "BEST_EFFORT", "VOLATILE")
    reliable = all(p.qos.reliability == "RELIABLE" for p in publishers)
    durable = all(p.qos.durability == "TRANSIENT_LOCAL" for p in publishers)
    if durable:  # KEEP_ALL publishers (depth 0) count as the default depth
        depth = sum(p.qos.depth or SUBSCRIBE_DEPTH for p in publishers)
    else:
        depth = max(p.qos.depth for p in publishers) or SUBSCRIBE_DEPTH
    return QoS(
        "KEEP_LAST", depth, "RELIABLE" if reliable else "BEST_EFFORT", "TRANSIENT_LOCAL" if durable else "VOLATILE"
    )


def _node(
    config: pb.RobotConfig,
    node: pb.Node,
    name: str,
    index: int,
    declared: list[topology.Declaration],
    publishers: dict[str, list[Endpoint]],
    simulated_by: str,
) -> NodeModel:
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
        # the node's own topic_name, state_topic or odom_topic; the runtime derives /diagnostics and the preset channel
        if not item.implied and len(item.at) == len(node_path(index)) + 1:
            fields[item.at[-1]] = endpoint
    topic, state, odom = fields.get("topic_name"), fields.get("state_topic"), fields.get("odom_topic")
    devices = tuple(_devices(node, name))
    compressed = fields.get(image_transport.COMPRESSED_FIELD)
    settings = node_settings.for_node(config, node, name, topic, state, inputs, odom, compressed)
    return NodeModel(
        host=placement.node_host(config, node),
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
        yield Device("camera", f"/dev/video{defaults.camera_index(node)}", name)
    if "model_path" in claims and node.model_path and not node.model_path.startswith(REGISTRY_PREFIX):
        yield Device("model", node.model_path, name)


def _written_files(config: pb.RobotConfig, nodes: tuple[NodeModel, ...]) -> frozenset[str]:
    """Files a node of the robot writes while it runs (a calibration node's calibration_file): never an input,
    or every save would restart the nodes that read it."""
    return frozenset(
        model.settings.calibration_file
        for node, model in zip(config.node, nodes)
        if defaults.entry(node).family == Family.CALIBRATION and model.settings.calibration_file
    )


def _file_named(reference: str) -> tuple[str, ...]:
    """The file a model reference names (a URDF or MJCF path), none for a `builtin:` one."""
    return (reference,) if reference and not reference.startswith(BUILTIN_PREFIX) else ()


def _inputs(node: pb.Node, settings, written: frozenset[str]) -> tuple[str, ...]:
    """The files a node reads as it starts: its calibration, its URDF, a CUSTOM program given by path."""
    files = [settings.calibration_file] if settings.calibration_file else []
    files += _file_named(settings.robot_description)
    if node.type == pb.CUSTOM and "/" in node.executable:
        files.append(node.executable)
    return tuple(dict.fromkeys(path for path in files if path not in written))


def _process(config: pb.RobotConfig, node: pb.Node, model: NodeModel, written: frozenset[str]) -> Process:
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
        carries_images=custom or _carries_images(model),
        inputs=_inputs(node, model.settings, written),
    )


def _carries_images(model: NodeModel) -> bool:
    return any(e.message_type in IMAGE_TYPES for e in model.publishes + model.subscribes)


def _cpp_args(model: NodeModel) -> tuple[str, ...]:
    """`--ros-args -r __node:=NAME -p field:=value ...` for the C++ binary of a node."""
    settings = model.settings
    values = {
        "topic_name": settings.topic.name,
        "message_type": settings.topic.message_type,
        "qos_depth": settings.qos.depth,
        "qos_reliability": settings.qos.reliability,
        "qos_durability": settings.qos.durability,
        "qos_history": settings.qos.history,
        "state_topic": settings.state_topic.name,
        "preset": json.dumps({p.name: dict(p.positions) for p in settings.preset}) if settings.preset else "",
    }
    args = ["--ros-args", "-r", f"__node:={model.name}"]
    for key in NODE_TYPES[model.type].cpp_parameters:
        value = values[key] if key in values else getattr(settings, key)
        if not isinstance(value, (str, int, float)):
            value = list(value)
        if value in ("", [], -1):
            continue
        args += ["-p", f"{key}:={escape.ros_parameter(value)}"]
    return tuple(args)


def _foxglove_settings(config: pb.RobotConfig, topics: tuple[Topic, ...]):
    """The Foxglove bridge serves every typed topic, subscribed with a QoS all its publishers serve."""
    served = [
        Endpoint(defaults.FOXGLOVE_NAME, t.name, t.message_type, _matching_qos(list(t.publishers)), "subscriber")
        for t in topics
        if t.message_type
    ]
    return node_settings.for_foxglove(config, defaults.FOXGLOVE_NAME, served)


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
