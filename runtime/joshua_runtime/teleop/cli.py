"""`joshua-teleop`: drive a mobile base (DIFF_DRIVE_BASE, its mock or its simulation) from a keyboard or a gamepad.

    joshua-teleop                       keys in this terminal -> Twist on /cmd_vel
    joshua-teleop --joy /joy            sensor_msgs/msg/Joy (e.g. from a joy node) -> Twist on /cmd_vel

The Twist is published RELIABLE at --rate-hz, so a base's command timeout stops it only when this
program stops; quitting (Esc or Ctrl-D at the keyboard, SIGINT, SIGTERM) publishes a zero Twist first.
"""

import argparse
import os
import select
import signal
import sys
import termios
import threading
import tty

from joshua_runtime.ros_node import create_ros_node
from joshua_runtime.ros_teardown import leave_ros
from joshua_runtime.teleop.mapping import KeyboardTeleop, joy_velocity

KEY_HELP = "w/s forward/back, a/d turn, q/e/z/c curves, space stop, +/- speed, Esc quit"
QUIT_KEYS = ("\x1b", "\x03", "\x04")
READ_SIZE = 16
# Longest the loop waits for DDS before it looks at the keyboard again.
SPIN_SLICE_S = 0.02
# Longest an exit waits for subscribers to acknowledge the final zero Twist.
STOP_ACK_TIMEOUT_S = 2.0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="joshua-teleop", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--topic", default="/cmd_vel", help="Twist topic of the base")
    parser.add_argument("--joy", default="", help="read sensor_msgs/msg/Joy from this topic instead of keys")
    parser.add_argument("--max-linear", type=float, default=0.2, help="top linear speed, m/s")
    parser.add_argument("--max-angular", type=float, default=2.0, help="top turning speed, rad/s")
    parser.add_argument("--rate-hz", type=float, default=10.0, help="Twist publication rate")
    parser.add_argument("--linear-axis", type=int, default=1, help="Joy axis that drives")
    parser.add_argument("--angular-axis", type=int, default=0, help="Joy axis that turns")
    parser.add_argument("--enable-button", type=int, default=-1, help="Joy button to hold while driving (-1: none)")
    return parser


def split_keys(data: str) -> list[str]:
    """Keys of one terminal read: arrow keys are three characters (ESC [ A), every other key one."""
    keys, i = [], 0
    while i < len(data):
        if data.startswith("\x1b[", i) and i + 2 < len(data):
            keys.append(data[i : i + 3])
            i += 3
        else:
            keys.append(data[i])
            i += 1
    return keys


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.rate_hz <= 0 or args.max_linear < 0 or args.max_angular < 0:
        print("joshua-teleop: error: --rate-hz must be above 0 and the top speeds at least 0", file=sys.stderr)
        return 2
    keyboard = None if args.joy else sys.stdin
    if keyboard is not None and not keyboard.isatty():
        print("joshua-teleop: error: keys are read from a terminal; use --joy TOPIC otherwise", file=sys.stderr)
        return 2

    import rclpy
    from geometry_msgs.msg import Twist
    from rclpy.duration import Duration
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rclpy.signals import SignalHandlerOptions
    from sensor_msgs.msg import Joy

    stop = threading.Event()
    for number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(number, lambda _signum, _frame: stop.set())
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = create_ros_node("joshua_teleop")
    publisher = node.create_publisher(Twist, args.topic, QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
    teleop = KeyboardTeleop(args.max_linear, args.max_angular)
    state = {"velocity": (0.0, 0.0)}

    def publish() -> None:
        msg = Twist()
        msg.linear.x, msg.angular.z = state["velocity"]
        publisher.publish(msg)

    def on_joy(msg) -> None:
        state["velocity"] = joy_velocity(
            msg.axes,
            msg.buttons,
            args.max_linear,
            args.max_angular,
            args.linear_axis,
            args.angular_axis,
            args.enable_button,
        )

    if args.joy:
        node.create_subscription(Joy, args.joy, on_joy, 10)
    node.create_timer(1.0 / args.rate_hz, publish)
    saved = termios.tcgetattr(keyboard) if keyboard is not None else None
    try:
        if keyboard is not None:
            tty.setcbreak(keyboard.fileno())
            print(f"joshua-teleop: {KEY_HELP}\r", flush=True)
        while not stop.is_set():
            rclpy.spin_once(node, timeout_sec=SPIN_SLICE_S)
            if keyboard is None or not select.select([keyboard], [], [], 0)[0]:
                continue
            data = os.read(keyboard.fileno(), READ_SIZE).decode(errors="replace")
            if not data or any(key in QUIT_KEYS for key in split_keys(data)):
                break
            for key in split_keys(data):
                teleop.press(key)
            state["velocity"] = teleop.velocity()
            print("joshua-teleop: linear {:.2f} m/s, angular {:.2f} rad/s\r".format(*state["velocity"]), flush=True)
    finally:
        if saved is not None:
            termios.tcsetattr(keyboard, termios.TCSADRAIN, saved)
        state["velocity"] = (0.0, 0.0)
        publish()
        # A reliable sample still in the writer's queue dies with the process: wait for its acknowledgement.
        if not publisher.wait_for_all_acked(Duration(seconds=STOP_ACK_TIMEOUT_S)):
            print("joshua-teleop: warning: the zero Twist was not acknowledged by every subscriber", file=sys.stderr)
        leave_ros(None, node)
    return 0


if __name__ == "__main__":
    sys.exit(main())
