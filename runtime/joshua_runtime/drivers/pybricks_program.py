"""The hub program as Pybricks downloads it: pybricks_hub_program.py compiled to MPY v6, in a multi-file blob.

A blob is, per module, `<u32 little-endian size><name>\0<mpy>`; the hub runs the module `__main__`.
"""

from importlib import resources

from joshua_runtime.errors import DeviceError

PROGRAM_SOURCE = "pybricks_hub_program.py"
MAIN_MODULE = "__main__"
MPY_V6_MAGIC = b"M\x06"


def program_source() -> str:
    return resources.files("joshua_runtime.drivers").joinpath(PROGRAM_SOURCE).read_text(encoding="utf-8")


def program_blob() -> bytes:
    """The compiled hub program (needs mpy-cross-v6, part of the `lego` extra)."""
    try:
        import mpy_cross_v6
    except ImportError:
        raise DeviceError("mpy-cross-v6 is not installed: install joshua-runtime[lego]") from None
    process, mpy = mpy_cross_v6.mpy_cross_compile(PROGRAM_SOURCE, program_source())
    if process.returncode != 0 or mpy is None:
        raise DeviceError(f"the hub program does not compile: {process.stderr.strip()}")
    return multi_file_blob({MAIN_MODULE: mpy})


def multi_file_blob(modules: dict[str, bytes]) -> bytes:
    return b"".join(len(mpy).to_bytes(4, "little") + name.encode() + b"\0" + mpy for name, mpy in modules.items())


def main_module(blob: bytes) -> bytes | None:
    """The `__main__` MPY of a blob; None when the blob is not a well-formed multi-file blob."""
    offset = 0
    while offset + 4 < len(blob):
        size = int.from_bytes(blob[offset : offset + 4], "little")
        end_of_name = blob.find(b"\0", offset + 4)
        if end_of_name < 0 or end_of_name + 1 + size > len(blob):
            return None
        name, mpy = blob[offset + 4 : end_of_name], blob[end_of_name + 1 : end_of_name + 1 + size]
        if name == MAIN_MODULE.encode():
            return mpy
        offset = end_of_name + 1 + size
    return None
