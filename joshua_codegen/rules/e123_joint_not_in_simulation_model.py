"""E123 joint-not-in-simulation-model: a simulated servo node or base names a joint the built-in model lacks.

What it checks:
    In MODE_SIMULATION with a built-in model (`builtin:so100`), every joint of every servo node that
    the simulation stands in for ({servo_types}) is a joint of that model: its `joint_names`, or the
    names derived from `device_ids` (`joint_<id>` unless there are six ids).

    The same holds for the wheel joints of a simulated {base_types} (`builtin:lego_bot`: left_wheel, right_wheel).

Why it matters:
    The simulation drives and reads joints by name; the simulated node refuses to start when one is
    not in the model.

Example:
    simulation { model: "builtin:so100" }
    node {
      type: ACTUATOR_SUBSCRIBER
      joint_names: ["pan", "lift", "elbow", "wrist", "roll", "grip"]   # error: joint "pan" is not in ...
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.models import BUILTIN_MODEL_JOINTS, BUILTIN_PREFIX
from joshua_core.node_families import Family
from joshua_core.schema import robot_config_pb2 as pb

TYPE_LISTS = {
    "servo_types": lambda entry: entry.servo_bus and entry.hardware,
    "base_types": lambda entry: entry.family == Family.BASE and entry.hardware,
}
CODE = "E123"
NAME = "joint-not-in-simulation-model"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    model = ctx.config.simulation.model
    joints = BUILTIN_MODEL_JOINTS.get(model.removeprefix(BUILTIN_PREFIX)) if model.startswith(BUILTIN_PREFIX) else None
    if ctx.config.mode != pb.MODE_SIMULATION or joints is None:
        return
    known = ", ".join(joints)
    for view in ctx.typed_nodes:
        simulated_joints = view.node.type in defaults.SERVO_BUS or view.node.type in defaults.BASES
        if not simulated_joints or view.node.type not in defaults.HARDWARE:
            continue
        for k, name in enumerate(defaults.joint_names(view.node)):
            if name in joints:
                continue
            if view.node.joint_names:
                yield Finding(
                    view.at("joint_names", k),
                    f'joint "{name}" is not in the simulation model "{model}" (its joints: {known})',
                )
            else:
                yield Finding(
                    view.at("device_ids"),
                    f"{view.label} gets the joint names {', '.join(defaults.joint_names(view.node))} "
                    f'from its device_ids, which "{model}" lacks; set joint_names '
                    f"to joints of the model ({known})",
                )
                break
