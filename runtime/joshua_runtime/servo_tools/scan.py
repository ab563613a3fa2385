"""Find every servo on a bus at every STS3215 baud rate, and notice ids that two servos share."""

from collections import Counter
from dataclasses import dataclass

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import BAUD_RATE_CODES, decode_value, register
from joshua_runtime.drivers.sts3215_transport import REPLY_TIMEOUT_S, Expected, GarbledReply, NoAnswer
from joshua_runtime.errors import DeviceError
from joshua_runtime.servo_tools.bus import TOOL_RETRIES

BROADCAST_QUIET_S = 0.02  # after a reply to a broadcast PING, this much silence ends the round
# Per id when pinging every id one by one: the drivers' window, which outlasts the 16 ms an FTDI
# adapter holds a short reply by default (a shorter one finds no servo behind such an adapter), and a
# silent id is asked twice, as the tools ask every servo: a reply that comes late once is not a miss.
SWEEP_REPLY_TIMEOUT_S = REPLY_TIMEOUT_S
SWEEP_RETRIES = TOOL_RETRIES
MODEL_NAMES = {777: "sts3215"}


@dataclass(frozen=True)
class FoundServo:
    id: int
    model: int
    baud_rate: int
    firmware: str

    @property
    def model_name(self) -> str:
        return MODEL_NAMES.get(self.model, f"model {self.model}")

    def as_json(self) -> dict:
        return {"id": self.id, "model": self.model_name, "baud_rate": self.baud_rate, "firmware": self.firmware}


@dataclass(frozen=True)
class ScanResult:
    servos: list[FoundServo]
    shared_ids: list[tuple[int, int]]  # (id, baud rate) answered by more than one servo


def scan(bus, baud_rates=tuple(BAUD_RATE_CODES)) -> ScanResult:
    """Broadcast a PING at each rate, then identify each answering id with an addressed READ.

    When the broadcast's replies arrive garbled (servos that answer a broadcast at once), every id
    is pinged one by one at that rate instead.
    """
    servos, shared = [], []
    for baud_rate in baud_rates:
        bus.transport.set_baud_rate(baud_rate)
        packets, garbled = bus.transport.collect(proto.encode(proto.BROADCAST_ID, proto.INST_PING), BROADCAST_QUIET_S)
        counts = Counter(packet.servo_id for packet in packets if packet.servo_id <= proto.MAX_SERVO_ID)
        if garbled:
            counts = ping_every_id(bus)
        for servo_id in sorted(counts):
            if counts[servo_id] > 1:
                shared.append((servo_id, baud_rate))
                continue
            try:
                servos.append(identify(bus, servo_id, baud_rate))
            except GarbledReply:
                shared.append((servo_id, baud_rate))
            except NoAnswer:
                continue
    return ScanResult(servos, shared)


def ping_every_id(bus, ids=range(proto.MAX_SERVO_ID + 1)) -> Counter:
    """The ids among `ids` (default: every id) answering an addressed PING (a garbled answer counts twice: a
    shared id)."""
    transport = bus.transport
    saved = transport.reply_timeout_s, transport.max_retries
    transport.reply_timeout_s, transport.max_retries = SWEEP_REPLY_TIMEOUT_S, SWEEP_RETRIES
    counts = Counter()
    try:
        for servo_id in ids:
            try:
                transport.transact(proto.encode(servo_id, proto.INST_PING), [Expected(servo_id, 0)])
                counts[servo_id] = 1
            except GarbledReply:
                counts[servo_id] = 2
            except DeviceError:
                if not transport.is_open:
                    raise
    finally:
        transport.reply_timeout_s, transport.max_retries = saved
    return counts


def identify(bus, servo_id: int, baud_rate: int) -> FoundServo:
    """Model number and firmware version of one servo, read in one READ (addresses 0 to 4)."""
    bus.transport.set_baud_rate(baud_rate)
    major, minor, model = (
        register(name) for name in ("Firmware_Major_Version", "Firmware_Minor_Version", "Model_Number")
    )
    data = bus.read_bytes(servo_id, major.address, model.address + model.size - major.address)

    def value(reg):
        return decode_value(reg, data[reg.address - major.address :])

    return FoundServo(servo_id, value(model), baud_rate, f"{value(major)}.{value(minor)}")


def find(bus, servo_id: int, baud_rates=tuple(BAUD_RATE_CODES)) -> FoundServo:
    """Where one id answers; NoAnswer when no rate reaches it, GarbledReply when two servos share it."""
    for baud_rate in baud_rates:
        try:
            return identify(bus, servo_id, baud_rate)
        except NoAnswer:
            continue
    raise NoAnswer(f"{bus.port}: no answer from servo id {servo_id} at any baud rate")
