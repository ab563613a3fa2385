"""Packet encoding, decoding, resynchronisation and sign-magnitude values of the SCS protocol."""

from hypothesis import given
from hypothesis import strategies as st

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215_table import decode_value, encode_value, register


def test_encode_matches_the_documented_packets():
    assert proto.encode(1, proto.INST_PING).hex(" ") == "ff ff 01 02 01 fb"
    assert proto.encode(1, 0).hex(" ") == "ff ff 01 02 00 fc"
    assert proto.encode(1, proto.INST_READ, bytes([0x38, 2])).hex(" ") == "ff ff 01 04 02 38 02 be"
    assert proto.encode(1, 0, bytes([0x18, 0x05])).hex(" ") == "ff ff 01 04 00 18 05 dd"
    assert proto.encode_sync_read(0x38, 8, [1, 2]).hex(" ") == "ff ff fe 06 82 38 08 01 02 36"
    status = bytes.fromhex("0008 0000 0000 791e")
    assert proto.encode(1, 0, status).hex(" ") == "ff ff 01 0a 00 00 08 00 00 00 00 79 1e 55"


def test_sync_write_layout():
    packet = proto.encode_sync_write(42, 2, {1: b"\x00\x08", 2: b"\xff\x0f"})
    assert packet[:5] == bytes([0xFF, 0xFF, 0xFE, (2 + 1) * 2 + 4, proto.INST_SYNC_WRITE])
    assert packet[5:-1] == bytes([42, 2, 1, 0x00, 0x08, 2, 0xFF, 0x0F])


def test_parser_skips_garbage_and_resyncs_after_a_bad_frame():
    parser = proto.PacketParser()
    good = proto.encode(3, proto.INST_PING)
    bad = bytearray(proto.encode(4, proto.INST_PING))
    bad[-1] ^= 0xFF
    parser.feed(b"\x00\x13\xff" + bytes(bad) + b"\xff\xff\xff" + good[2:] + good)
    first = parser.pop()
    assert (first.servo_id, first.checksum_ok) == (4, False)
    assert parser.pop() == proto.Packet(3, proto.INST_PING, b"", True)
    assert parser.pop() == proto.Packet(3, proto.INST_PING, b"", True)
    assert parser.pop() is None
    assert parser.pending == 0


def test_parser_waits_for_a_split_packet():
    parser = proto.PacketParser()
    packet = proto.encode(7, 0, b"\x01\x02\x03")
    parser.feed(packet[:5])
    assert parser.pop() is None
    assert parser.bytes_wanted() == len(packet) - 5
    parser.feed(packet[5:])
    assert parser.pop().params == b"\x01\x02\x03"


def test_parser_rejects_impossible_lengths():
    parser = proto.PacketParser()
    parser.feed(b"\xff\xff\x01\xff\x00" + proto.encode(2, 0))
    assert parser.pop().servo_id == 2


@given(st.integers(min_value=-32767, max_value=32767))
def test_sign_magnitude_round_trip_bit_15(value):
    raw = proto.to_sign_magnitude(value, 15)
    assert raw < 1 << 16
    assert proto.from_sign_magnitude(raw, 15) == value


def test_sign_magnitude_examples():
    assert proto.to_sign_magnitude(-5, 15) == 0x8005
    assert proto.to_sign_magnitude(-100, 10) == 0x0400 | 100
    assert proto.to_sign_magnitude(-3000, 11) == 0x0800 | 2047  # saturates at the magnitude width
    assert proto.from_sign_magnitude(0x0864, 11) == -100


def test_register_values_are_little_endian_with_their_sign_bit():
    offset = register("Homing_Offset")
    assert encode_value(offset, -12) == bytes([12, 0x08])
    assert decode_value(offset, bytes([12, 0x08])) == -12
    assert encode_value(register("Model_Number"), 777) == b"\x09\x03"
    assert decode_value(register("Present_Load"), (0x400 | 250).to_bytes(2, "little")) == -250


def test_error_text_names_the_bits():
    assert proto.error_text(proto.ERROR_OVERHEAT | proto.ERROR_VOLTAGE) == "input voltage, overheat"
