"""E405 unsupported-baud-rate: a baud rate the device cannot use.

What it checks:
    A servo-bus node (encoder, actuator, calibration, and their mocks) sets a `baud_rate` the
    STS3215 supports: 1000000, 500000, 250000, 128000, 115200, 76800, 57600 or 38400. A lidar
    node sets 230400, the LDS-01's fixed rate.

Why it matters:
    At any other rate every byte is garbled and the device never answers.

Example:
    node {
      type: ENCODER_PUBLISHER
      baud_rate: 9600            # error: the STS3215 does not support 9600 baud
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR
from joshua_codegen.rules.context import Finding
from joshua_core.devices import LDS01_BAUD_RATE, STS3215_BAUD_RATES

CODE = "E405"
NAME = "unsupported-baud-rate"
SEVERITY = ERROR
STAGE = "check"
SERVO_NODES = defaults.SERVO_BUS | defaults.ENCODERS | defaults.ACTUATORS


def check(ctx):
    rates = ", ".join(str(rate) for rate in STS3215_BAUD_RATES)
    for view in ctx.typed_nodes:
        node = view.node
        if not node.HasField("baud_rate"):
            continue
        if node.type in defaults.LIDARS and node.baud_rate != LDS01_BAUD_RATE:
            yield Finding(
                view.at("baud_rate"), f"the LDS-01 lidar runs at {LDS01_BAUD_RATE} baud, not {node.baud_rate}"
            )
        elif node.type in SERVO_NODES and node.baud_rate not in STS3215_BAUD_RATES:
            yield Finding(
                view.at("baud_rate"), f"the STS3215 does not support {node.baud_rate} baud; use one of {rates}"
            )
