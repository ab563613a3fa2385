"""Ask a Fast DDS Discovery Server whether it answers, with one RTPS participant announcement (standard library only).

UDP has no handshake, so "the port is open" cannot be told from silence. The probe speaks the server's
own protocol instead: it sends the DATA(p) a client sends first (RTPS 2.3, eProsima vendor id, a
random GUID prefix, its metatraffic locator the address and port of a socket of the probe), and the
server, which takes any client that announces itself, answers at once from its own GUID prefix. The
probe then withdraws (a DATA(Up): disposed and unregistered), so the server forgets it and tells no
one; it announced no endpoint, so no ROS node ever sees it.

Outcomes: answered (round trip, and which server: the prefix names its `-i` id); "nothing listens"
(the host answered with ICMP port unreachable: up, but no server on that port); no route; or no
answer within the timeout (host down, link down, or packets dropped). Standard library only, so a
supervisor or any tool can copy or import it without ROS.
"""

import errno
import os
import select
import socket
import struct
import time
from dataclasses import dataclass

PROBE_TIMEOUT_S = 1.0
SERVER_PREFIX = bytes.fromhex("44 53 00 5f 45 50 52 4f 53 49 4d 41")  # `-i ID` sets byte 2 to ID
SERVER_ID_BYTE = 2
VENDOR_EPROSIMA = b"\x01\x0f"  # the server ignores announcements of other vendors
PROTOCOL_VERSION = b"\x02\x03"
RTPS_HEADER = b"RTPS" + PROTOCOL_VERSION + VENDOR_EPROSIMA
# Entity ids of the participant-discovery (SPDP) endpoints and of a participant itself (RTPS 9.3.1.3).
PARTICIPANT_ENTITY = b"\x00\x00\x01\xc1"
SPDP_WRITER, SPDP_READER = b"\x00\x01\x00\xc2", b"\x00\x01\x00\xc7"
DATA_SUBMESSAGE = 0x15
FLAG_LITTLE_ENDIAN, FLAG_INLINE_QOS, FLAG_DATA = 0x01, 0x02, 0x04
PL_CDR_LE = b"\x00\x03\x00\x00"  # encapsulation of a parameter list, little endian
LOCATOR_KIND_UDPV4 = 1
# Parameter ids (RTPS 9.6.2.2.2; 0x0083 as Fast DDS reads it for its server).
PID_SENTINEL, PID_PARTICIPANT_LEASE_DURATION, PID_PROTOCOL_VERSION, PID_VENDORID = 0x0001, 0x0002, 0x0015, 0x0016
PID_DEFAULT_UNICAST_LOCATOR, PID_METATRAFFIC_UNICAST_LOCATOR = 0x0031, 0x0032
PID_PARTICIPANT_GUID, PID_BUILTIN_ENDPOINT_SET = 0x0050, 0x0058
PID_KEY_HASH, PID_STATUS_INFO, PID_RELATED_SAMPLE_IDENTITY = 0x0070, 0x0071, 0x0083
PARTICIPANT_ANNOUNCER_AND_DETECTOR = 0x3  # builtin endpoints announced: SPDP writer and reader only
PROBE_LEASE_S = 2  # how long the server keeps the probe should the withdrawal be lost
DISPOSED_UNREGISTERED = b"\x00\x00\x00\x03"
RECEIVE_BYTES = 65536


@dataclass(frozen=True)
class ProbeResult:
    answered: bool
    detail: str  # one line: who answered and how fast, or why there was no answer
    round_trip_s: float | None = None
    server_id: int | None = None  # from the answering server's GUID prefix


def _parameter(pid: int, value: bytes) -> bytes:
    padding = b"\x00" * (-len(value) % 4)
    return struct.pack("<HH", pid, len(value) + len(padding)) + value + padding


def _locator(address: str, port: int) -> bytes:
    return struct.pack("<iI", LOCATOR_KIND_UDPV4, port) + b"\x00" * 12 + socket.inet_aton(address)


def _data(prefix: bytes, sequence: int, flags: int, inline_qos: bytes, payload: bytes = b"") -> bytes:
    """An RTPS message holding one SPDP DATA submessage from the participant `prefix`."""
    body = (
        struct.pack("<HH", 0, 16)  # extra flags, octets to inline QoS (from here to the inline QoS)
        + SPDP_READER
        + SPDP_WRITER
        + struct.pack("<iI", 0, sequence)
        + inline_qos
        + payload
    )
    submessage = struct.pack("<BBH", DATA_SUBMESSAGE, flags, len(body)) + body
    return RTPS_HEADER + prefix + submessage


def _inline_qos(prefix: bytes, sequence: int, *extra: bytes) -> bytes:
    identity = prefix + SPDP_WRITER + struct.pack("<iI", 0, sequence)
    return b"".join(
        [
            _parameter(PID_KEY_HASH, prefix + PARTICIPANT_ENTITY),
            _parameter(PID_RELATED_SAMPLE_IDENTITY, identity),
            *extra,
            _parameter(PID_SENTINEL, b""),
        ]
    )


def announcement(prefix: bytes, address: str, port: int, sequence: int = 1) -> bytes:
    """The DATA(p) of a client participant `prefix` whose metatraffic goes to address:port."""
    parameters = [
        _parameter(PID_PROTOCOL_VERSION, PROTOCOL_VERSION),
        _parameter(PID_VENDORID, VENDOR_EPROSIMA),
        _parameter(PID_PARTICIPANT_GUID, prefix + PARTICIPANT_ENTITY),
        _parameter(PID_METATRAFFIC_UNICAST_LOCATOR, _locator(address, port)),
        _parameter(PID_DEFAULT_UNICAST_LOCATOR, _locator(address, port)),
        _parameter(PID_PARTICIPANT_LEASE_DURATION, struct.pack("<iI", PROBE_LEASE_S, 0)),
        _parameter(PID_BUILTIN_ENDPOINT_SET, struct.pack("<I", PARTICIPANT_ANNOUNCER_AND_DETECTOR)),
        _parameter(PID_SENTINEL, b""),
    ]
    flags = FLAG_LITTLE_ENDIAN | FLAG_INLINE_QOS | FLAG_DATA
    return _data(prefix, sequence, flags, _inline_qos(prefix, sequence), PL_CDR_LE + b"".join(parameters))


def withdrawal(prefix: bytes, sequence: int = 2) -> bytes:
    """The DATA(Up) that removes participant `prefix` from the server (disposed and unregistered)."""
    status = _parameter(PID_STATUS_INFO, DISPOSED_UNREGISTERED)
    return _data(prefix, sequence, FLAG_LITTLE_ENDIAN | FLAG_INLINE_QOS, _inline_qos(prefix, sequence, status))


def answering_server(message: bytes) -> int | None:
    """The `-i` id of the Discovery Server that sent this RTPS message, None when it is not one's."""
    if len(message) < 20 or not message.startswith(b"RTPS"):
        return None
    sender = message[8:20]
    if sender[:SERVER_ID_BYTE] + sender[SERVER_ID_BYTE + 1 :] != SERVER_PREFIX[:SERVER_ID_BYTE] + SERVER_PREFIX[3:]:
        return None
    return sender[SERVER_ID_BYTE]


def probe(address: str, port: int, server_id: int | None = None, timeout_s: float = PROBE_TIMEOUT_S) -> ProbeResult:
    """Whether the Discovery Server at address:port answers within `timeout_s` (and is `server_id`, when given)."""
    where = f"{address}:{port}"
    prefix = VENDOR_EPROSIMA + os.urandom(10)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sender:
        try:
            sender.connect((address, port))
            local_address = sender.getsockname()[0]
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as receiver:
                receiver.bind((local_address, 0))
                started = time.monotonic()
                sender.send(announcement(prefix, local_address, receiver.getsockname()[1]))
                result = _await_answer(sender, receiver, where, started, timeout_s)
                if result.answered:
                    sender.send(withdrawal(prefix))
        except ConnectionRefusedError:
            return ProbeResult(False, f"nothing listens on {where} (its host answered: port unreachable)")
        except OSError as exc:
            reason = "no route to the host" if exc.errno in (errno.ENETUNREACH, errno.EHOSTUNREACH) else exc.strerror
            return ProbeResult(False, f"cannot reach {where}: {reason}")
    if result.answered and server_id is not None and result.server_id != server_id:
        return ProbeResult(False, f"the server on {where} has id {result.server_id}, not {server_id}", None)
    return result


def _await_answer(sender, receiver, where: str, started: float, timeout_s: float) -> ProbeResult:
    deadline = started + timeout_s
    while (remaining := deadline - time.monotonic()) > 0:
        readable, _, _ = select.select([receiver, sender], [], [], remaining)
        if sender in readable:
            sender.recv(RECEIVE_BYTES)  # raises ConnectionRefusedError on ICMP port unreachable
        if receiver in readable:
            server = answering_server(receiver.recv(RECEIVE_BYTES))
            if server is not None:
                round_trip = time.monotonic() - started
                return ProbeResult(
                    True,
                    f"discovery server {server} on {where} answered in {1000 * round_trip:.1f} ms",
                    round_trip,
                    server,
                )
    return ProbeResult(False, f"no answer from {where} within {timeout_s:g} s")
