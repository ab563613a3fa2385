"""The SO-100/101 arm: joint names in servo-id order and approximate joint ranges."""

SO100_JOINTS = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper")
# Servo ids of the joints on the arm's bus, in SO100_JOINTS order.
SO100_SERVO_IDS = (1, 2, 3, 4, 5, 6)

# Approximate joint ranges in rad of the SO-100/101 (as public MuJoCo models of the arm give them).
SO100_RANGES = {
    "shoulder_pan": (-1.92, 1.92),
    "shoulder_lift": (-1.75, 1.75),
    "elbow_flex": (-1.69, 1.69),
    "wrist_flex": (-1.66, 1.66),
    "wrist_roll": (-2.74, 2.74),
    "gripper": (-0.17, 1.75),
}
