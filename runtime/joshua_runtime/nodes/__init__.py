"""rclpy node classes, one per node type (see entrypoint.NODE_CLASSES)."""
