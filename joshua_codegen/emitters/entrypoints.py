"""nodes/<name>.py: one executable entrypoint per Python process, holding its resolved settings."""

from joshua_codegen.model import Robot
from joshua_codegen.render import Context, template
from joshua_core.settings import to_literal


def emit(robot: Robot, context: Context) -> dict[str, str]:
    files = {}
    for process in robot.processes:
        if process.kind != "python":
            continue
        files[process.entrypoint] = template(
            "node_entrypoint.py.j2", robot=robot, process=process, settings=to_literal(robot.process_settings(process))
        )
    return files
