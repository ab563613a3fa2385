"""The hub line protocol and Pybricks GATT values: framing, checksums, garbage, capabilities, program blob."""

import pytest

from joshua_runtime.drivers import pybricks_protocol as hub
from joshua_runtime.drivers.pybricks_program import MPY_V6_MAGIC, main_module, multi_file_blob


def test_a_line_round_trips_with_its_checksum():
    line = hub.encode_line("V", 7, 90.0, -45.5)
    assert line.endswith(b"\n")
    assert hub.decode_line(line[:-1]) == ["V", "7", "90", "-45.5"]


@pytest.mark.parametrize("bad", [b"V,7,90,-45*00", b"V,7,90,-45", b"*41", b"\xff\xfe*00", b"A,1,2,3*G1"])
def test_a_line_with_bad_framing_is_dropped(bad):
    assert hub.decode_line(bad) is None


def test_lines_split_anywhere_and_wrapped_in_garbage_are_recovered():
    stream = b"\x00\xffjunk\n" + hub.encode_line("A", 10, 1, 2) + b"#$%" + hub.encode_line("K", 3) + b"x" * 200
    assembler = hub.LineAssembler()
    found = []
    for i in range(0, len(stream), 7):
        found += assembler.feed(stream[i : i + 7])
    assert found == [["A", "10", "1", "2"], ["K", "3"]]
    assert assembler.rejected >= 2
    assert assembler.feed(hub.encode_line("K", 4)) == [["K", "4"]]


def test_capabilities_unpack_the_hub_format():
    caps = hub.Capabilities(max_write=158, flags=2, max_program=32768, slots=1)
    assert hub.unpack_capabilities(hub.pack_capabilities(caps)) == caps
    with pytest.raises(ValueError):
        hub.unpack_capabilities(b"\x00" * 10)


def test_the_hub_program_compiles_to_an_mpy_v6_main_module(blob):
    assert main_module(blob).startswith(MPY_V6_MAGIC)
    assert main_module(multi_file_blob({"other": b"M\x06"})) is None
    assert main_module(b"\xff\xff\xff\xff__main__\0") is None
