"""Base class of every runtime node and the loop that runs one until SIGINT or SIGTERM.

A node class receives its NodeSettings (the settings contract, joshua_core.settings), creates its publishers, subscriptions and timers in `start()`, and
releases its device in `close()`. `run()` owns rclpy: it installs its own SIGINT/SIGTERM handlers,
spins until a signal ends the loop (a signal wakes the executor's wait at once, so an idle node does not
poll), then closes the node and returns exit code 0.

Readiness (sd_notify, see notify.py): a node is ready when `start()` returns, unless its class sets
`ready_later` and calls `announce_ready()` itself once its background loading is done. Announcing logs
one "ready: ..." line with what the node serves and sends READY=1 to the process manager; the loop
pings the manager's watchdog while it spins.
"""

import sys

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from joshua_core.settings import NodeSettings, TopicSettings
from joshua_runtime.errors import JoshuaError
from joshua_runtime.messages import message_class
from joshua_runtime.notify import Notifier
from joshua_runtime.qos import qos_profile
from joshua_runtime.ros_node import create_ros_node
from joshua_runtime.ros_teardown import leave_ros
from joshua_runtime.stop_signal import SignalWake, StopRequested, StopSignal

# The longest an idle node's loop waits before it looks at its stop flag anyway (a signal wakes it at once).
IDLE_WAIT_S = 2.0
# Topics every rclpy node has; not part of what a node serves.
INFRASTRUCTURE_TOPICS = ("/rosout", "/parameter_events")


class JoshuaNode:
    """One ROS 2 node configured by joshuac settings. Subclasses override start() and close()."""

    ready_later = False  # True: start() leaves loading to a thread, which calls announce_ready() when done

    def __init__(self, settings: NodeSettings, ros_node: Node):
        self.settings = settings
        self.ros = ros_node
        self.log = ros_node.get_logger()
        self.notifier = Notifier(None)
        self.is_ready = False

    @property
    def name(self) -> str:
        return self.settings.name

    def start(self) -> None:
        """Open devices and create publishers, subscriptions and timers."""

    def close(self) -> None:
        """Release devices. Called once, after spinning stops, also after a failed start."""

    def serving(self) -> str:
        """What the node serves, for its ready line: the topics it publishes and subscribes, its rate, its device."""
        published = sorted({p.topic_name for p in self.ros.publishers} - set(INFRASTRUCTURE_TOPICS))
        subscribed = sorted({s.topic_name for s in self.ros.subscriptions} - set(INFRASTRUCTURE_TOPICS))
        parts = []
        if published:
            parts.append(f"publishing {', '.join(published)}")
        if subscribed:
            parts.append(f"subscribing {', '.join(subscribed)}")
        if self.settings.rate_hz:
            parts.append(f"at {self.settings.rate_hz:g} Hz")
        device = self.settings.serial_port or self.settings.video_source
        if device:
            parts.append(f"on {device}")
        return " ".join(parts) or "no topics"

    def announce_ready(self, detail: str = "") -> None:
        """Log the ready line and tell the process manager (READY=1); later calls do nothing."""
        if self.is_ready:
            return
        self.is_ready = True
        summary = (f"{detail}; " if detail else "") + self.serving()
        self.log.info(f"ready: {summary}")
        self.notifier.ready(summary)

    def publisher(self, topic: TopicSettings):
        """Create a publisher for a topic of the settings."""
        return self.ros.create_publisher(message_class(topic.message_type), topic.name, qos_profile(topic.qos))

    def subscription(self, topic: TopicSettings, callback):
        """Create a subscription for a topic of the settings."""
        return self.ros.create_subscription(
            message_class(topic.message_type), topic.name, callback, qos_profile(topic.qos)
        )

    def stamp(self):
        """The node clock's now() as a builtin_interfaces/Time."""
        return self.ros.get_clock().now().to_msg()


def run(node_class: type[JoshuaNode], settings: NodeSettings, stop: StopSignal | None = None) -> int:
    """Run one node until SIGINT or SIGTERM; return the process exit code.

    A signal during start-up ends the node cleanly too (exit code 0): a robot stopped while a node
    is still importing its libraries or opening its device must not wait for that to finish.
    """
    stop = stop or StopSignal().install()
    ros_node = executor = node = wake = None
    notifier = Notifier.from_environment()
    code = 0
    try:
        rclpy.init(args=None, signal_handler_options=SignalHandlerOptions.NO)
        ros_node = create_ros_node(settings.name)
        executor = SingleThreadedExecutor()
        executor.add_node(ros_node)
        wake = SignalWake(ros_node.create_guard_condition(lambda: None).trigger)
        node = node_class(settings, ros_node)
        node.notifier = notifier
        node.start()
        stop.starting = False
        if not node.ready_later:
            node.announce_ready()
        wait_s = min(IDLE_WAIT_S, notifier.watchdog_interval_s / 4) if notifier.watchdog_interval_s else IDLE_WAIT_S
        while not stop.event.is_set():
            notifier.watchdog()
            executor.spin_once(timeout_sec=wait_s)
        notifier.stopping()
    except StopRequested:
        pass
    except JoshuaError as exc:
        print(f"{settings.name}: error: {exc}", file=sys.stderr, flush=True)
        code = exc.exit_code
    finally:
        stop.starting = False
        if wake is not None:
            wake.close()
        if node is not None:
            try:
                node.close()
            except JoshuaError as exc:
                print(f"{settings.name}: error while closing: {exc}", file=sys.stderr, flush=True)
                code = code or exc.exit_code
        # An exception none of the above handled ends the process with 1, also should the teardown hang.
        propagating = sys.exc_info()[1] is not None
        leave_ros(executor, ros_node, exit_code=1 if propagating else code)
        notifier.close()
    return code
