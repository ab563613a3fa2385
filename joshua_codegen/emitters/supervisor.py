"""supervisor.py: the standalone process supervisor of a robot (fork/exec, restarts, signal cascade)."""

from joshua_codegen.emitters import fastdds, process_launch
from joshua_codegen.model import Process, Robot
from joshua_codegen.render import Context, template

SUPERVISOR_PATH = "supervisor.py"


def process_data(process: Process) -> dict:
    """What the supervisor needs to launch one node, as plain data."""
    return {
        "name": process.name,
        "type": process.node_type,
        "kind": process.kind,
        "entrypoint": process.entrypoint,
        "executable": process.executable,
        "args": list(process.args),
        "cpp_binary": process.cpp_binary,
        "cpp_args": list(process.cpp_args),
        "restart": process.restart,
        "max_restarts": process.max_restarts,
        "critical": process.critical,
        "env": dict(process.env),
        "devices": [{"kind": device.kind, "path": device.path} for device in process.devices],
    }


def supervisor_data(robot: Robot) -> dict:
    """The one literal the generated supervisor reads; paths are relative to its directory."""
    return {
        "name": robot.name,
        "ros_domain_id": robot.ros_domain_id,
        "cpp_bin_dir": robot.cpp_bin_dir,
        "fastdds_profile": fastdds.PROFILE_PATH,
        "processes": [process_data(process) for process in robot.processes],
    }


def emit(robot: Robot, context: Context) -> dict[str, str]:
    text = template("supervisor.py.j2", robot=robot, data=supervisor_data(robot), policy=process_launch)
    return {SUPERVISOR_PATH: text}
