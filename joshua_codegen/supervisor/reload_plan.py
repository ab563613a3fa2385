"""What a reload changes: every process of the running build and of the new one compared by name."""

import os

# What a process runs with: a change to any restarts it. Its other fields (restart policy, critical, what
# preflight checks) are taken over as they are, without a restart.
COMMAND_KEYS = ("kind", "entrypoint", "executable", "args", "cpp_binary", "cpp_args")
# The robot's data a reload applies besides the processes (through them: every process gets `env`, the
# C++ nodes look in `cpp_bin_dir`). Any other difference (the supervisor's code, formats, names) needs a
# restart of the robot.
RELOADED_ROBOT_KEYS = ("env", "cpp_bin_dir", "processes")
IDENTITY_KEYS = ("name", "host")  # which robot a build is of (a robot on several hosts: which host's part)


def build_refusal(running, new) -> str | None:
    """Why the build `new` cannot be reloaded into the robot running `running` (both Builds), or None."""
    old_robot, new_robot = running.robot, new.robot
    if any(old_robot.get(key) != new_robot.get(key) for key in IDENTITY_KEYS):
        return f"a build of {robot_label(new_robot)}, not of {robot_label(old_robot)}"
    if old_robot.get("supervisor_code") != new_robot.get("supervisor_code"):
        return (
            f"built by another joshuac (supervisor code {new_robot.get('supervisor_code')!s:.16}, this one runs "
            f"{old_robot.get('supervisor_code')!s:.16}): restart the robot from it instead"
        )
    for key in sorted(set(old_robot) | set(new_robot)):
        if key not in RELOADED_ROBOT_KEYS + IDENTITY_KEYS and old_robot.get(key) != new_robot.get(key):
            return f"its {key} differs from the running build's: restart the robot from it instead"
    return None


def robot_label(robot: dict) -> str:
    host = robot.get("host")
    return f"robot {robot.get('name')!r:.80}" + (f" (host {host!r:.80})" if host else "")


def file_mark(path: str):
    """What tells a file's versions apart without reading it: device, inode, size, modification time; None when
    it is missing. A file saved by renaming a new one over it, or written in place, gets a new mark."""
    try:
        info = os.stat(path)
    except OSError:
        return None
    return (info.st_dev, info.st_ino, info.st_size, info.st_mtime_ns)


def input_marks(paths) -> dict:
    """The file_mark of every input of a node, taken as it launches."""
    return {path: file_mark(path) for path in paths}


def launch_changes(running, old: dict, new_build, new: dict) -> list[str]:
    """What differs in how process `old` of Build `running` and `new` of `new_build` run, in words; [] when alike."""
    changes = []
    cpp_dirs = (running.robot["cpp_bin_dir"], new_build.robot["cpp_bin_dir"]) if new["cpp_binary"] else ("", "")
    if [old[key] for key in COMMAND_KEYS] != [new[key] for key in COMMAND_KEYS] or cpp_dirs[0] != cpp_dirs[1]:
        changes.append("command line")
    if {**running.robot["env"], **old["env"]} != {**new_build.robot["env"], **new["env"]}:
        changes.append("environment")
    if new["entrypoint"] and running.files.get(old["entrypoint"]) != new_build.files.get(new["entrypoint"]):
        changes.append("settings")
    old_profile, new_profile = running.files.get(old["fastdds_profile"]), new_build.files.get(new["fastdds_profile"])
    if old["fastdds_profile"] != new["fastdds_profile"] or old_profile != new_profile:
        changes.append("DDS profile")
    if old["inputs"] != new["inputs"]:
        changes.append("files it reads")
    return changes


def changed_inputs(marks: dict) -> list[str]:
    """The inputs whose file changed since `marks` (input_marks at the node's launch) were taken."""
    return [path for path, mark in marks.items() if file_mark(path) != mark]


class ReloadPlan:
    """The processes of a reload, by name: `restart` ({name: what changed}), `start` and `stop` (names of added
    and removed ones), `update` ({name: fields taken over without a restart}) and `keep` (names, unchanged)."""

    def __init__(self):
        self.restart: dict[str, str] = {}
        self.start: list[str] = []
        self.stop: list[str] = []
        self.update: dict[str, str] = {}
        self.keep: list[str] = []


def plan_reload(running, nodes, new_build) -> ReloadPlan:
    """The plan that turns the robot of Build `running` and its Nodes `nodes` (input marks of their last launch)
    into the robot of `new_build`. Raises KeyError or TypeError when the new build's data has another shape."""
    plan = ReloadPlan()
    current = {node.name: node for node in nodes}
    for new in new_build.robot["processes"]:
        node = current.get(new["name"])
        if node is None:
            plan.start.append(new["name"])
            continue
        changes = launch_changes(running, node.spec, new_build, new) + [
            f"{path} changed" for path in changed_inputs(node.input_marks) if path in new["inputs"]
        ]
        others = sorted(key for key in set(node.spec) | set(new) if node.spec.get(key) != new.get(key))
        others = [key for key in others if key not in COMMAND_KEYS + ("env", "fastdds_profile", "inputs")]
        if changes:
            plan.restart[node.name] = ", ".join(changes)
        elif others:
            plan.update[node.name] = ", ".join(others)
        else:
            plan.keep.append(node.name)
    names = {spec["name"] for spec in new_build.robot["processes"]}
    plan.stop = [node.name for node in nodes if node.name not in names]
    return plan
