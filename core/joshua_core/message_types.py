"""The ROS message types the node types and tools name: the one place their type strings are written."""

JOINT_STATE = "sensor_msgs/msg/JointState"
# An action chunk: timed joint positions, as ros2_control's joint_trajectory_controller takes them.
JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
# What a joint command topic carries: one goal per message, or a chunk of timed goals.
JOINT_COMMAND_TYPES = (JOINT_STATE, JOINT_TRAJECTORY)
TWIST = "geometry_msgs/msg/Twist"
ODOMETRY = "nav_msgs/msg/Odometry"
IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
LASER_SCAN = "sensor_msgs/msg/LaserScan"
# What a policy can observe and a dataset can record: images and joint states.
OBSERVATION_TYPES = IMAGE_TYPES + (JOINT_STATE,)
