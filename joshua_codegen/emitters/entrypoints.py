"""nodes/<name>.py: one executable entrypoint per Python process, holding its resolved settings
(the dashboard's, the Discovery Server's and the host agents' hold their command-line arguments instead)."""

from joshua_codegen.model import Robot
from joshua_codegen.render import Context, template
from joshua_core import control_plane, discovery
from joshua_core.dashboard import PROCESS_TYPE as DASHBOARD_TYPE
from joshua_core.settings import to_literal


def emit(robot: Robot, context: Context) -> dict[str, str]:
    files = {}
    for process in robot.processes:
        if process.kind != "python":
            continue
        if process.node_type == DASHBOARD_TYPE:
            files[process.entrypoint] = template("dashboard_entrypoint.py.j2", robot=robot, process=process)
            continue
        if process.node_type == control_plane.PROCESS_TYPE:
            files[process.entrypoint] = template(
                "host_agent_entrypoint.py.j2", robot=robot, process=process, module=control_plane.RUNTIME_MODULE
            )
            continue
        if process.node_type == discovery.PROCESS_TYPE:
            files[process.entrypoint] = template(
                "discovery_server_entrypoint.py.j2", robot=robot, process=process, module=discovery.RUNTIME_MODULE
            )
            continue
        files[process.entrypoint] = template(
            "node_entrypoint.py.j2", robot=robot, process=process, settings=to_literal(robot.process_settings(process))
        )
    return files
