"""`leave_ros`: how a process that is about to end shuts its executor, node and ROS context down."""

from joshua_runtime.exit_timer import exit_after

TEARDOWN_DEADLINE_S = 2.0  # the DDS goodbye takes 0.01-0.3 s; the supervisor escalates to SIGTERM after 5 s


def leave_ros(executor, node, context=None, exit_code: int = 0) -> None:
    """Shut `executor` and destroy `node` (either may be None), then shut `context` (rclpy's default: None) down.

    Deleting the DDS participant can deadlock in Fast DDS 2.14 (exit_timer.py); should it take longer
    than TEARDOWN_DEADLINE_S, the process ends there with `exit_code`, the code it was about to end with.
    """
    import rclpy

    with exit_after(TEARDOWN_DEADLINE_S, exit_code):
        if executor is not None:
            executor.shutdown(timeout_sec=0)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown(context=context)
