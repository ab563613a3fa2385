"""The processes joshuac adds beside the described nodes: simulation engine, Foxglove bridge, dashboard,
and on a robot of several hosts each host's agent and the Discovery Server."""

from dataclasses import replace

from joshua_codegen import defaults, placement
from joshua_codegen.model import ControlRouter, DiscoveryServer, Host, Process
from joshua_core import control_plane
from joshua_core import dashboard as dashboard_facts
from joshua_core import discovery as discovery_facts
from joshua_core.node_types import FOXGLOVE_BRIDGE, SIMULATION_ENGINE
from joshua_core.schema import robot_config_pb2 as pb


def control_router(config: pb.RobotConfig, hosts: tuple[Host, ...]) -> ControlRouter | None:
    """Where the hosts' agents meet, with `control { }`: the control host's address and port, over TLS when
    the hosts hold certificates."""
    if not config.HasField("control"):
        return None
    name = placement.control_host(config)
    address = next(h.address for h in hosts if h.name == name)
    credentials = {field: getattr(config.control, field) for field in control_plane.CREDENTIAL_FIELDS}
    tls = control_plane.uses_tls(credentials)
    return ControlRouter(name, control_plane.endpoint(address, placement.control_port(config), tls))


def host_agent_process(config: pb.RobotConfig, host: Host, hosts: tuple[Host, ...]) -> Process:
    """The agent of one host: it reports the Discovery Server's reachability to its supervisor and, with
    `control { }`, joins the other hosts' agents over Zenoh (the control host's agent listens, the others
    connect), with the paths of its host's credentials; the router's dictionary only on the router's host."""
    args = []
    router = control_router(config, hosts)
    if router is not None:
        args += ["--listen" if host.name == router.host else "--connect", router.endpoint]
        for field in control_plane.CREDENTIAL_FIELDS:
            path = getattr(config.control, field)
            if path and (field != "users_file" or host.name == router.host):
                args += [control_plane.credential_flag(field), path]
    process = service_process(control_plane.process_name(host.name), control_plane.PROCESS_TYPE, False, False, args)
    return replace(process, host=host.name)


def discovery_process(server: DiscoveryServer) -> Process:
    """The Fast DDS Discovery Server: critical (no process of any host finds another without it), started
    before the other processes of its host."""
    args = ["--address", server.address, "--port", str(server.port)]
    process = service_process(discovery_facts.PROCESS_NAME, discovery_facts.PROCESS_TYPE, True, False, args)
    return replace(process, host=server.host, starts_first=True)


def service_process(
    name: str, node_type: str, critical: bool, carries_images: bool, args=(), env=(), inputs=()
) -> Process:
    """A Python process joshuac adds beside the described nodes, restarted on failure."""
    return Process(
        name=name,
        node_type=node_type,
        kind="python",
        entrypoint=f"nodes/{name}.py",
        executable="",
        args=tuple(args),
        cpp_binary="",
        cpp_args=(),
        restart="RESTART_ON_FAILURE",
        max_restarts=defaults.MAX_RESTARTS,
        critical=critical,
        env=tuple(env),
        devices=(),
        carries_images=carries_images,
        inputs=tuple(inputs),
    )


def engine_process(name: str, carries_images: bool, inputs: tuple[str, ...]) -> Process:
    """The simulation engine: critical, as the simulated robot is nothing without it. Its input: the MJCF file."""
    return service_process(name, SIMULATION_ENGINE.name, True, carries_images, inputs=inputs)


def foxglove_process(name: str, carries_images: bool) -> Process:
    """The bridge process: not critical (a viewer must not stop the robot)."""
    return service_process(name, FOXGLOVE_BRIDGE.name, False, carries_images)


def dashboard_process(config: pb.RobotConfig, carries_images: bool) -> Process:
    """The web dashboard: its entrypoint runs `python -m joshua_runtime.dashboard` with `args`; it
    subscribes to every topic, images included when the robot has some."""
    dashboard = config.dashboard
    port = dashboard.port if dashboard.HasField("port") else dashboard_facts.DEFAULT_PORT
    args = ["--port", str(port), "--bind", dashboard.bind or dashboard_facts.DEFAULT_BIND]
    if dashboard.zenoh_connect:
        args += ["--zenoh-connect", dashboard.zenoh_connect]
    for name in dashboard.allowed_host:
        args += ["--allowed-host", name]
    for field in dashboard_facts.FLEET_CREDENTIAL_FIELDS:  # paths only: the dashboard reads the files
        if getattr(dashboard, field):
            args += [dashboard_facts.credential_flag(field), getattr(dashboard, field)]
    return service_process(
        dashboard_facts.PROCESS_NAME,
        dashboard_facts.PROCESS_TYPE,
        False,
        carries_images,
        args,
        sorted(config.env.items()),
    )
