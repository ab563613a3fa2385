"""The SO-100/101 arm: joint names in servo-id order (the compiler's defaults) and approximate ranges."""

from joshua_codegen.defaults import SO100_JOINTS

# Joint ranges in rad (spec/protocols.md section 3), in SO100_JOINTS order.
SO100_RANGES = {
    "shoulder_pan": (-1.92, 1.92),
    "shoulder_lift": (-1.75, 1.75),
    "elbow_flex": (-1.69, 1.69),
    "wrist_flex": (-1.66, 1.66),
    "wrist_roll": (-2.74, 2.74),
    "gripper": (-0.17, 1.75),
}

__all__ = ["SO100_JOINTS", "SO100_RANGES"]
