"""The Discovery Server as a node of a supervisor: started, announced ready once it serves, stopped on a signal.

    python -m joshua_runtime.discovery.supervised --address 10.0.0.2 [--port 11811] [--server-id 0] [--profile XML]

The generated entrypoint of the `discovery_server` process runs this. It starts `fast-discovery-server`
as server.py would, passes its output on, sends READY=1 (sd_notify) when the server prints that it
is running (it has bound its UDP port by then), feeds the watchdog systemd asks for, and hands SIGINT
and SIGTERM to the server; its exit code is the server's (0 when a stop signal ended it). Exit code 2
with one line when the binary is missing or the arguments are bad.
"""

import os
import selectors
import signal
import subprocess
import sys

from joshua_runtime.discovery import server
from joshua_runtime.notify import Notifier

RUNNING_LINE = "Server is running"  # what fast-discovery-server prints once it serves
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
WAKE_S = 1.0  # how often the watchdog is looked at while the server runs
STOP_TIMEOUT_S = 5.0  # the server's own shutdown, after which it is killed
EXIT_USAGE = 2


def main(argv: list[str] | None = None) -> int:
    args = server.arguments("python -m joshua_runtime.discovery.supervised", __doc__.splitlines()[0], argv)
    problem = server.cannot_start(args)
    if problem:
        print(problem, file=sys.stderr)
        return EXIT_USAGE
    notifier = Notifier.from_environment()
    stop_requested = []
    read_signal, write_signal = os.pipe()
    os.set_blocking(write_signal, False)
    signal.set_wakeup_fd(write_signal, warn_on_full_buffer=False)
    for number in STOP_SIGNALS:
        signal.signal(number, lambda number, _frame: stop_requested.append(number))
    child = subprocess.Popen(
        server.command(args.address, args.port, args.server_id, args.profile),
        env=server.environment(dict(os.environ)),  # without the nodes' client profile
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
    )
    selector = selectors.DefaultSelector()
    selector.register(child.stdout, selectors.EVENT_READ)
    selector.register(read_signal, selectors.EVENT_READ)
    pending = b""
    announced = False
    while child.poll() is None:
        if stop_requested:
            child.send_signal(stop_requested.pop(0))
            notifier.stopping()
        for key, _ in selector.select(WAKE_S):
            if key.fileobj == read_signal:
                os.read(read_signal, 4096)
                continue
            data = os.read(child.stdout.fileno(), 65536)
            if not data:
                selector.unregister(child.stdout)
                continue
            sys.stdout.buffer.write(data)
            sys.stdout.flush()
            pending = (pending + data)[-4096:]
            if not announced and RUNNING_LINE.encode() in pending:
                announced = True
                notifier.ready(f"Discovery Server listening on UDP {args.address}:{args.port}")
        notifier.watchdog()
    try:
        code = child.wait(STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        child.kill()
        code = child.wait()
    rest = child.stdout.read()
    if rest:
        sys.stdout.buffer.write(rest)
        sys.stdout.flush()
    return 0 if stop_requested_or_clean(code) else (code if code > 0 else 128 - code)


def stop_requested_or_clean(code: int) -> bool:
    """The server ended as asked: exit code 0, or death by the stop signal it was handed."""
    return code == 0 or -code in STOP_SIGNALS


if __name__ == "__main__":
    sys.exit(main())
