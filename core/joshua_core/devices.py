"""Facts of the devices both the compiler and the runtime know: serial speeds of the servo bus and the lidar,
Bluetooth addresses and controllers of the Pybricks hub."""

import re

# STS3215 baud rates and the code each is written as in the servo's baud-rate register (address 6; Feetech's
# STS memory table; codes 5-7 as feetech-servo-sdk 1.0.0 and LeRobot 0.4.4 use them).
STS3215_BAUD_RATE_CODES = {
    1_000_000: 0,
    500_000: 1,
    250_000: 2,
    128_000: 3,
    115_200: 4,
    76_800: 5,
    57_600: 6,
    38_400: 7,
}
STS3215_BAUD_RATES = tuple(STS3215_BAUD_RATE_CODES)
STS3215_DEFAULT_BAUD_RATE = 1_000_000
# The LDS-01 lidar streams at one fixed speed.
LDS01_BAUD_RATE = 230_400

# A Bluetooth device address, six hex bytes; anything else a base's `hub` names is the hub's advertised name.
BLE_ADDRESS = re.compile(r"[0-9A-Fa-f]{2}(:[0-9A-Fa-f]{2}){5}")
# A name in one advertising packet: 31 bytes of payload less the field's length and type bytes.
BLE_NAME_MAX_BYTES = 29
# Kinds of Bumble transports that lead to a Bluetooth controller (`KIND` or `KIND:PARAMETERS`).
BLE_TRANSPORT_KINDS = (
    "usb",
    "serial",
    "tcp-client",
    "udp",
    "unix",
    "hci-socket",
    "vhci",
    "ws-client",
    "pty",
    "file",
    "android-emulator",
    "android-netsim",
)
