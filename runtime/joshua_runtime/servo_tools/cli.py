"""`joshua-servo`: bring up an STS3215 bus at the bench.

    joshua-servo find-port                    which device appears when the adapter is plugged in
    joshua-servo scan /dev/ttyACM0 [--json]   every servo at every baud rate
    joshua-servo ping /dev/ttyACM0 3
    joshua-servo set-id /dev/ttyACM0 1 4
    joshua-servo set-baud /dev/ttyACM0 4 500000
    joshua-servo status /dev/ttyACM0 [--json]
    joshua-servo calibrate /dev/ttyACM0 --robot so100 --role follower --output follower.json
    joshua-servo calibrate /dev/ttyACM0 --output follower.json --joints wrist_flex   # redo one joint

Exit codes: 0 done, 1 other failure, 2 bad usage, 3 device error, 4 port busy, 5 no answer or
calibration refused (the joints that passed are saved), 6 two servos share an id.
"""

import argparse
import json
import shlex
import sys
from pathlib import Path

from joshua_runtime.drivers import sts3215_status
from joshua_runtime.drivers.calibration import load_calibration
from joshua_runtime.drivers.sts3215 import DEFAULT_BAUD_RATE
from joshua_runtime.drivers.sts3215_table import BAUD_RATE_CODES
from joshua_runtime.drivers.sts3215_transport import GarbledReply, NoAnswer, PortBusy
from joshua_runtime.errors import JoshuaError
from joshua_runtime.servo_tools import configure, find_port, scan, status
from joshua_runtime.servo_tools.bus import open_bus
from joshua_runtime.servo_tools.calibration_flow import ARMS, CalibrationError
from joshua_runtime.servo_tools.configure import UsageError

EXIT_USAGE = 2
EXIT_PORT_BUSY = 4
EXIT_NO_ANSWER = 5
EXIT_SHARED_ID = 6
# This command's own codes; a node meeting the same errors exits with the runtime's (errors.py).
EXIT_CODES = (
    (UsageError, EXIT_USAGE),
    (PortBusy, EXIT_PORT_BUSY),
    (NoAnswer, EXIT_NO_ANSWER),
    (CalibrationError, EXIT_NO_ANSWER),
)


def _scan(args) -> int:
    with open_bus(args.port) as bus:
        result = scan.scan(bus)
    if args.json:
        print(json.dumps([servo.as_json() for servo in result.servos]))
    else:
        for servo in result.servos:
            print(f"id {servo.id:3d}  {servo.model_name}  {servo.baud_rate} baud  firmware {servo.firmware}")
    for servo_id, baud_rate in result.shared_ids:
        print(
            f"joshua-servo: error: two servos share id {servo_id} at {baud_rate} baud (their replies collide)",
            file=sys.stderr,
        )
    if result.shared_ids:
        return EXIT_SHARED_ID
    if not result.servos:
        print(f"joshua-servo: error: no servo answered on {args.port} at any baud rate", file=sys.stderr)
        return EXIT_NO_ANSWER
    return 0


def _describe(servo: scan.FoundServo) -> str:
    return f"id {servo.id}: {servo.model_name} (model {servo.model}), firmware {servo.firmware}, {servo.baud_rate} baud"


def _ping(args) -> int:
    with open_bus(args.port) as bus:
        print(_describe(scan.find(bus, args.id)))
    return 0


def _set_id(args) -> int:
    with open_bus(args.port) as bus:
        print(_describe(configure.set_id(bus, args.old, args.new)))
    return 0


def _set_baud(args) -> int:
    with open_bus(args.port) as bus:
        print(_describe(configure.set_baud(bus, args.id, args.baud)))
    return 0


def _status(args) -> int:
    with open_bus(args.port, args.baud) as bus:
        ids = args.ids or [s.id for s in scan.scan(bus, [args.baud]).servos]
        if not ids:
            raise NoAnswer(f"{args.port}: no servo answered at {args.baud} baud")
        bus.transport.set_baud_rate(args.baud)
        statuses = sts3215_status.read_status(bus, ids)
    if args.json:
        print(json.dumps([s.as_json() for s in statuses]))
    else:
        print(status.format_table(statuses))
    return 0


def _find_port(args) -> int:
    def lister():
        return find_port.list_devices(args.pattern or find_port.DEVICE_PATTERNS)

    if args.watch is not None:
        print(f"waiting up to {args.watch:g} s for a serial device to appear or vanish...", flush=True)
        change = find_port.watch_for_change(lister, args.watch)
    else:
        change = find_port.find_port_interactive(lister, input)
    print(change.describe())
    return 0 if change.appeared or change.vanished else 1


def _calibrate(args) -> int:
    from joshua_runtime.servo_tools.calibrate_terminal import calibrate

    output = args.output or Path(f"{args.robot}_{args.role}.json")
    arm = ARMS[args.robot]
    unknown = [joint for joint in args.joints or () if joint not in arm.joints]
    if unknown:
        raise UsageError(f"{args.robot} has no joint {', '.join(unknown)} (joints: {', '.join(arm.joints)})")
    kept = {}
    if args.joints and output.exists():  # redo some joints, keep the others of the file
        kept = {joint: motor for joint, motor in load_calibration(output).items() if joint not in args.joints}
    elif output.exists() and not args.force:
        raise UsageError(f"{output} exists; pass --force to replace it")
    with open_bus(args.port, args.baud, list(arm.ids)) as bus:
        failed = calibrate(bus, arm, output, args.joints, kept)
    if failed:
        attempted = args.joints or arm.joints
        saved = f"; the other joints are saved in {output}" if kept or len(failed) < len(attempted) else ""
        just = "just it" if len(failed) == 1 else "just them"
        raise CalibrationError(
            f"{'; '.join(failed.values())}{saved}. Redo {just}: {_redo_command(args, output, failed)}"
        )
    return 0


def _redo_command(args, output: Path, joints) -> str:
    """The command that calibrates only `joints` into `output`, keeping its other joints."""
    words = ["joshua-servo", "calibrate", args.port, "--robot", args.robot, "--role", args.role]
    if args.baud != DEFAULT_BAUD_RATE:
        words += ["--baud", str(args.baud)]
    return shlex.join([*words, "--output", str(output), "--joints", ",".join(joints)])


def _joints(text: str) -> tuple[str, ...]:
    joints = tuple(part.strip() for part in text.split(",") if part.strip())
    if not joints:
        raise argparse.ArgumentTypeError("expected comma-separated joint names")
    return joints


def _ids(text: str) -> list[int]:
    try:
        return [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated servo ids, got {text!r}") from None


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="joshua-servo", description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = parser.add_subparsers(dest="command", required=True)
    command = sub.add_parser("scan", help="find every servo at every baud rate")
    command.add_argument("port")
    command.add_argument("--json", action="store_true", help='print [{"id", "model", "baud_rate", "firmware"}]')
    command.set_defaults(run=_scan)
    command = sub.add_parser("ping", help="find one servo id at any baud rate")
    command.add_argument("port")
    command.add_argument("id", type=int)
    command.set_defaults(run=_ping)
    command = sub.add_parser("set-id", help="give a servo a new id (kept across power cycles)")
    command.add_argument("port")
    command.add_argument("old", type=int)
    command.add_argument("new", type=int)
    command.set_defaults(run=_set_id)
    command = sub.add_parser("set-baud", help="change a servo's baud rate (kept across power cycles)")
    command.add_argument("port")
    command.add_argument("id", type=int)
    command.add_argument("baud", type=int, help=", ".join(map(str, BAUD_RATE_CODES)))
    command.set_defaults(run=_set_baud)
    command = sub.add_parser("status", help="position, speed, load, voltage, temperature and errors per servo")
    command.add_argument("port")
    command.add_argument("--ids", type=_ids, help="servo ids (default: every servo answering)")
    command.add_argument("--baud", type=int, default=DEFAULT_BAUD_RATE)
    command.add_argument("--json", action="store_true")
    command.set_defaults(run=_status)
    command = sub.add_parser("find-port", help="which serial device is the servo adapter")
    command.add_argument("--watch", type=float, metavar="SECONDS", help="wait for a change instead of asking")
    command.add_argument("--pattern", action="append", help="device glob (repeatable; default /dev/tty* adapters)")
    command.set_defaults(run=_find_port)
    command = sub.add_parser("calibrate", help="guided per-joint calibration writing LeRobot JSON")
    command.add_argument("port")
    command.add_argument("--robot", choices=sorted(ARMS), default="so100")
    command.add_argument("--role", choices=("follower", "leader"), default="follower")
    command.add_argument("--output", type=Path, help="calibration file (default ROBOT_ROLE.json)")
    command.add_argument("--baud", type=int, default=DEFAULT_BAUD_RATE)
    command.add_argument("--force", action="store_true", help="replace an existing file")
    command.add_argument(
        "--joints",
        type=_joints,
        help="calibrate only these joints (comma-separated), keeping the others of an existing --output file",
    )
    command.set_defaults(run=_calibrate)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        return args.run(args)
    except GarbledReply as exc:
        print(f"joshua-servo: error: {exc} (two servos share this id?)", file=sys.stderr)
        return EXIT_SHARED_ID
    except JoshuaError as exc:
        print(f"joshua-servo: error: {exc}", file=sys.stderr)
        return next((code for kind, code in EXIT_CODES if isinstance(exc, kind)), exc.exit_code)
    except (EOFError, KeyboardInterrupt):
        print("joshua-servo: stopped", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
