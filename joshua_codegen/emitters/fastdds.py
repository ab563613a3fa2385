"""fastdds_profile.xml: the Fast DDS participant profile every node loads (large shared-memory segment)."""

from joshua_codegen.model import Robot
from joshua_codegen.render import Context, template

PROFILE_PATH = "fastdds_profile.xml"


def emit(robot: Robot, context: Context) -> dict[str, str]:
    return {PROFILE_PATH: template("fastdds_profile.xml.j2", robot=robot)}
