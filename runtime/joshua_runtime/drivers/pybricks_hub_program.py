"""Hub program (Pybricks MicroPython): drives two wheel motors from stdin lines, reports their angles on stdout.

Downloaded and started by drivers/pybricks.py; the line protocol is described in pybricks_protocol.py.
Left wheel on port A (mounted mirrored, so reversed), right wheel on port B.
"""

from pybricks.parameters import Direction, Port
from pybricks.pupdevices import Motor
from pybricks.tools import StopWatch, wait
from uselect import poll
from usys import stdin, stdout

REPORT_PERIOD_MS = 20
HUB_WATCHDOG_MS = 1000

left = Motor(Port.A, Direction.COUNTERCLOCKWISE)
right = Motor(Port.B)
clock = StopWatch()
keyboard = poll()
keyboard.register(stdin)


def checksum(body):
    value = 0
    for byte in body.encode():
        value ^= byte
    return value


def send(body):
    stdout.write(f"{body}*{checksum(body):02X}\n")


def decode(line):
    star = line.rfind("*")
    if star < 1 or len(line) - star != 3:
        return None
    body = line[:star]
    try:
        if int(line[star + 1 :], 16) != checksum(body):
            return None
    except ValueError:
        return None
    return body.split(",")


def apply(fields):
    if fields[0] == "V" and len(fields) == 4:
        left.run(float(fields[2]))
        right.run(float(fields[3]))
    elif fields[0] == "S" and len(fields) == 2:
        left.stop()
        right.stop()
    else:
        return
    send("K," + fields[1])


pending = ""
last_command = clock.time()
next_report = clock.time()
send("R")
while True:
    while keyboard.poll(0):
        char = stdin.read(1)
        if char == "\n":
            fields = decode(pending.strip())
            pending = ""
            if fields:
                try:
                    apply(fields)
                    last_command = clock.time()
                except ValueError:
                    pass
        elif len(pending) < 96:
            pending += char
        else:
            pending = ""
    now = clock.time()
    if now - last_command > HUB_WATCHDOG_MS:
        left.stop()
        right.stop()
        last_command = now
    if now >= next_report:
        send(f"A,{now},{left.angle()},{right.angle()}")
        next_report = now + REPORT_PERIOD_MS
    wait(1)
