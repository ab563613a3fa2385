"""`joshua-emulate`: serve an emulated device (on a pseudo-terminal, or Bluetooth HCI on TCP) until SIGINT or SIGTERM.

    joshua-emulate sts3215 --ids 1,2,3,4,5,6 --link /tmp/ttyLEADER
    joshua-emulate sts3215 --link /tmp/ttyLEADER --hand -      # joints moved by commands on stdin
    joshua-emulate lds01 --link /tmp/ttyLIDAR
    joshua-emulate pybricks --port 9100

pybricks: a Pybricks hub with two wheel motors on a virtual Bluetooth link. The emulator serves the
HCI of a virtual controller in range of the hub on 127.0.0.1:PORT; a base node reaches the hub by
setting `ble_transport: "tcp-client:127.0.0.1:PORT"` (hub "Pybricks Hub" or F4:B8:5E:00:00:01).
"""

import argparse
import signal
import sys


def _ids(text: str) -> list[int]:
    try:
        ids = [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated servo ids, got {text!r}") from None
    if not ids or any(not 0 <= i <= 253 for i in ids):
        raise argparse.ArgumentTypeError("servo ids must be 0-253")
    return ids


def _port(text: str) -> int:
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a TCP port number, got {text!r}") from None
    if not 1 <= port <= 65535:
        raise argparse.ArgumentTypeError("TCP ports are 1-65535")
    return port


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="joshua-emulate", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = parser.add_subparsers(dest="device", required=True)
    sts = sub.add_parser("sts3215", help="a Feetech STS3215 servo bus")
    sts.add_argument(
        "--ids", type=_ids, default=[1, 2, 3, 4, 5, 6], help="servo ids, e.g. 1,2,3 (1,1 wires two servos with id 1)"
    )
    sts.add_argument("--link", required=True, help="path of the symlink to the pty")
    sts.add_argument("--baud-rate", type=int, default=1_000_000, help="line speed the servos start at")
    sts.add_argument("--drop-rate", type=float, default=0.0, help="fraction of replies dropped")
    sts.add_argument("--corrupt-rate", type=float, default=0.0, help="fraction of replies with a bad checksum")
    sts.add_argument("--seed", type=int, default=0, help="seed of the fault injection")
    sts.add_argument(
        "--hand",
        type=argparse.FileType("r"),
        metavar="SCRIPT",
        help="move joints as a hand would, by commands read from SCRIPT (- for stdin): turn ID TICKS, "
        "sweep ID FROM TO [SECONDS], wait SECONDS; each answered 'hand: done ...' on stdout",
    )
    lds = sub.add_parser("lds01", help="an LDS-01 lidar streaming a synthetic room")
    lds.add_argument("--link", required=True, help="path of the symlink to the pty")
    lds.add_argument("--rpm", type=float, default=300.0, help="rotation speed")
    lds.add_argument("--corrupt-rate", type=float, default=0.0, help="fraction of corrupted packets")
    lds.add_argument("--seed", type=int, default=0, help="seed of the fault injection")
    hub = sub.add_parser("pybricks", help="a Pybricks hub with two wheel motors, over Bluetooth LE HCI on TCP")
    hub.add_argument("--port", type=_port, default=9100, help="TCP port of the HCI on 127.0.0.1")
    hub.add_argument("--name", default="Pybricks Hub", help="advertised hub name")
    hub.add_argument("--never-start", action="store_true", help="accept the program but never run it")
    hub.add_argument("--garbage-rate", type=float, default=0.0, help="fraction of stdout lines after garbage")
    hub.add_argument("--drop-link-after", type=int, default=0, help="drop the link on this stdin command")
    hub.add_argument("--seed", type=int, default=0, help="seed of the fault injection")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    stop = {"flag": False}

    def request_stop(_signum, _frame):
        stop["flag"] = True

    signal.signal(signal.SIGINT, request_stop)
    signal.signal(signal.SIGTERM, request_stop)
    if args.device == "sts3215":
        from joshua_runtime.emulators.sts3215 import serve
    elif args.device == "pybricks":
        from joshua_runtime.emulators.pybricks_link import serve
    else:
        from joshua_runtime.emulators.lds01 import serve
    try:
        serve(args, should_stop=lambda: stop["flag"])
    except (OSError, ValueError) as exc:
        print(f"joshua-emulate: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
