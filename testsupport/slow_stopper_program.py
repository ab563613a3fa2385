"""The slow-stopping node program of slow_stopper.py.

argv: LOG NAME EXTENSION_S ASK_EVERY_S ASKING_S exit|stay
"""

import os
import signal
import socket
import sys
import time


def main(log_path: str, name: str, extension_s: str, every_s: str, asking_s: str, then: str) -> None:
    address = os.environ["NOTIFY_SOCKET"]
    address = "\0" + address[1:] if address.startswith("@") else address

    def note(text: str) -> None:
        with open(log_path, "a") as log:
            log.write(f"{name} {os.getpid()} {text}\n")

    def on_sigterm(number, frame):
        note("got SIGTERM exit")
        os._exit(0)

    stopping = []
    signal.signal(signal.SIGINT, lambda number, frame: stopping.append(time.monotonic()))
    signal.signal(signal.SIGTERM, on_sigterm)
    note("start")
    while not stopping:
        time.sleep(0.01)
    note("got SIGINT saving")
    ask = f"EXTEND_TIMEOUT_USEC={int(float(extension_s) * 1e6)}\nSTATUS=saving".encode()
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sender:
        while time.monotonic() - stopping[0] < float(asking_s):
            sender.sendto(ask, address)
            time.sleep(float(every_s))
    if then == "exit":
        note("saved")
        os._exit(0)
    while True:
        time.sleep(1)


if __name__ == "__main__":
    main(*sys.argv[1:7])
