"""E414 invalid-ble-transport: a base's ble_transport does not name a Bluetooth controller transport.

What it checks:
    When written, `ble_transport` is `KIND` or `KIND:PARAMETERS` with KIND one of the controller
    transports of the Bumble BLE stack: usb, serial, tcp-client, udp, unix, hci-socket, vhci,
    ws-client, pty, file, android-emulator, android-netsim.

Why it matters:
    The base opens its Bluetooth controller at start-up; an unknown kind fails there, after the
    robot has started.

Example:
    node {
      type: DIFF_DRIVE_BASE
      ble_transport: "tcp:127.0.0.1:9100"   # error: ble_transport kind "tcp" is not one of usb, serial, ...
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.devices import BLE_TRANSPORT_KINDS

CODE = "E414"
NAME = "invalid-ble-transport"
SEVERITY = ERROR
STAGE = "check"


def check(ctx):
    kinds = ", ".join(BLE_TRANSPORT_KINDS)
    for view in ctx.nodes:
        transport = view.node.ble_transport
        if not transport:
            continue
        kind = transport.split(":", 1)[0]
        if kind not in BLE_TRANSPORT_KINDS:
            yield Finding(view.at("ble_transport"), f'ble_transport kind "{kind}" is not one of {kinds}')
