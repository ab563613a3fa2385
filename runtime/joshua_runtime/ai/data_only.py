"""A model directory is data: refuse, by name, any file whose loading could run code (pickles, code in processors).

Nothing here unpickles or imports what it inspects; pickles are recognised by their content where it
can be told, with pickletools (which only parses):
- a file that `pickle.load` would accept: its opening parses as pickle opcodes up to STOP, and
  either starts with the PROTO opcode of protocols 2 to 5 or uses an opcode that imports or calls
  (GLOBAL, REDUCE, ...: protocols 0 and 1 have no header). Text that happens to parse as a pickle
  of plain data ("N." opens a README) cannot run code and is kept;
- a zip archive (torch.save, stable-baselines3, numpy .npz) with such a member, at any depth;
- a stable-baselines3 save (its `data` member keeps fields as base64 cloudpickle, `:serialized:`);
- a numpy .npy array of Python objects (numpy stores them pickled);
- by name, whatever the content: `.pkl`, `.pickle`, `.joblib`, `.pt`, `.pth`, `.ckpt` in the file name.
A LeRobot processor pipeline (`policy_preprocessor.json`, `policy_postprocessor.json`) may only name
the registered data steps of ALLOWED_PROCESSOR_STEPS (a `class` entry is a Python import path that
LeRobot would import and call), and read its state from a safetensors file of the same directory.
A SmolVLA policy reads its backbone's configuration and tokenizer (JSON) from its own `vlm/` directory,
checked with the rest, or else from a Hugging Face Hub model named `owner/name`: a name that points
at a directory elsewhere on this machine is refused, as its files were never checked.
"""

import io
import json
import os
import pickletools
import re
import stat
import struct
import zipfile
from pathlib import Path, PurePosixPath

from joshua_runtime.ai.model_files import (
    ALLOWED_PROCESSOR_STEPS,
    CONFIG_FILE,
    PROCESSOR_FILES,
    SMOLVLA_BACKBONE,
    TOKENIZER_STEP,
)
from joshua_runtime.errors import SettingsError

PICKLE_SUFFIXES = (".pkl", ".pickle", ".joblib", ".pt", ".pth", ".ckpt")
# How much of a file is parsed as pickle opcodes: a payload sits at the start, and a megabyte of
# valid opcodes is no accident.
HEAD_BYTES = 1 << 20
# Archives inside archives (a torch.save zip inside a stable-baselines3 zip) are opened this deep,
# and read into memory up to this size.
ZIP_DEPTH = 4
NESTED_ZIP_BYTES = 256 << 20
_ZIP_MAGIC = b"PK\x03\x04"
_NPY_MAGIC = b"\x93NUMPY"
_SB3_SERIALIZED = b'":serialized:"'
_SB3_VERSION_MEMBER = "_stable_baselines3_version"
_HUB_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*/[A-Za-z0-9][A-Za-z0-9_.-]*")
# Opcodes through which unpickling imports a name or calls something.
_CODE_OPCODES = frozenset(
    {
        "GLOBAL",
        "STACK_GLOBAL",
        "INST",
        "OBJ",
        "NEWOBJ",
        "NEWOBJ_EX",
        "REDUCE",
        "BUILD",
        "EXT1",
        "EXT2",
        "EXT4",
        "PERSID",
        "BINPERSID",
    }
)
LEGACY_PPO_HINT = (
    " (stable-baselines3's own format, which joshua-train no longer writes: train again, or convert a policy "
    "of your own with `joshua-registry import DIR --name NAME --trust-pickle`)"
)


def check(directory: Path, shown_as: Path | None = None) -> None:
    """Refuse (SettingsError naming the file) a model directory holding a pickle or code in a processor pipeline.

    Files are named below `shown_as` instead of `directory` when given (a copy checked for its source)."""
    directory = Path(directory)
    shown = Path(shown_as) if shown_as is not None else directory
    for path in _files(directory):
        clause = file_clause(path)
        if clause is not None:
            hint = LEGACY_PPO_HINT if "stable-baselines3" in clause else ""
            raise SettingsError(
                f"{shown / path.relative_to(directory)} {clause}: loading it could run any code, "
                f"and a model must be data{hint}"
            )
    check_processor_steps(directory, shown)


def file_clause(path: Path) -> str | None:
    """What makes the file at `path` a pickle ("is a pickle", ...), or None when it is data."""
    suffix = _pickle_suffix(path.name)
    if suffix:
        return f"is named like a pickle or torch.save file ({suffix})"
    try:
        with open(path, "rb") as stream:
            head = stream.read(HEAD_BYTES)
            size = os.fstat(stream.fileno()).st_size
            clause = _content_clause(head, size)
            if clause is None and zipfile.is_zipfile(stream):
                clause = _zip_clause(stream, depth=1)
    except OSError as exc:
        raise SettingsError(f"cannot read {path}: {exc.strerror or exc}") from exc
    return clause


def check_processor_steps(directory: Path, shown_as: Path | None = None) -> None:
    """Refuse a saved processor pipeline that names Python code, an unknown step or a state file elsewhere."""
    shown = Path(shown_as) if shown_as is not None else Path(directory)
    allowed = ", ".join(ALLOWED_PROCESSOR_STEPS)
    for name in PROCESSOR_FILES:
        path = Path(directory) / name
        if not path.is_file():
            continue
        try:
            pipeline = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise SettingsError(f"cannot read {shown / name}: {exc}") from exc
        steps = pipeline.get("steps", []) if isinstance(pipeline, dict) else None
        if not isinstance(steps, list):
            raise SettingsError(f"{shown / name} holds no list of steps")
        for index, step in enumerate(steps):
            where = f"{shown / name}: step {index}"
            if not isinstance(step, dict):
                raise SettingsError(f"{where} is not an object")
            if "class" in step:
                raise SettingsError(
                    f"{where} names Python code to import ({step['class']}); "
                    f"only LeRobot's registered data steps are loaded ({allowed})"
                )
            if step.get("registry_name") not in ALLOWED_PROCESSOR_STEPS:
                raise SettingsError(f"{where} is {step.get('registry_name')!r}, not one of {allowed}")
            state_file = step.get("state_file")
            if state_file is not None and not _local_safetensors(Path(directory), state_file):
                raise SettingsError(
                    f"{where} reads {state_file!r}, which is not a safetensors file of the policy directory"
                )
            if step["registry_name"] == TOKENIZER_STEP:
                config = step.get("config") if isinstance(step.get("config"), dict) else {}
                _check_backbone_name(Path(directory), config.get("tokenizer_name"), f"{where} (its tokenizer)")
    config_path = Path(directory) / CONFIG_FILE
    try:
        config = json.loads(config_path.read_text()) if config_path.is_file() else {}
    except (OSError, ValueError) as exc:
        raise SettingsError(f"cannot read {shown / CONFIG_FILE}: {exc}") from exc
    if isinstance(config, dict) and "vlm_model_name" in config:
        _check_backbone_name(Path(directory), config["vlm_model_name"], f"{shown / CONFIG_FILE}: vlm_model_name")


def _check_backbone_name(directory: Path, name, where: str) -> None:
    """A SmolVLA backbone is the policy's own `vlm/` (loaded instead of `name`) or a Hub model `owner/name`."""
    if (directory / SMOLVLA_BACKBONE).is_dir() and not (directory / SMOLVLA_BACKBONE).is_symlink():
        return
    if not isinstance(name, str) or not _HUB_ID.fullmatch(name) or os.path.exists(name):
        raise SettingsError(
            f"{where} is {name!r}: neither the policy's own {SMOLVLA_BACKBONE}/ directory nor a Hugging Face Hub "
            "model (owner/name); files outside the policy directory are not loaded"
        )


def _files(directory: Path):
    """Every regular file at or below `directory`, following links to directories once each."""
    seen = set()
    for root, dirs, files in os.walk(directory, followlinks=True):
        status = os.stat(root)
        if (status.st_dev, status.st_ino) in seen:
            dirs[:] = []
            continue
        seen.add((status.st_dev, status.st_ino))
        dirs.sort()
        for name in sorted(files):
            path = Path(root, name)
            try:
                regular = stat.S_ISREG(os.stat(path).st_mode)
            except OSError:
                continue  # a dangling link: nothing to load
            if regular:
                yield path


def _pickle_suffix(name: str) -> str | None:
    return next((s for s in PurePosixPath(name.lower()).suffixes if s in PICKLE_SUFFIXES), None)


def _content_clause(head: bytes, size: int) -> str | None:
    if head.startswith(_NPY_MAGIC):
        return "is a numpy array of Python objects, which numpy stores as a pickle" if _npy_objects(head) else None
    if _opens_with_pickle(head, complete=len(head) >= size):
        return "is a pickle"
    return None


def _opens_with_pickle(data: bytes, complete: bool) -> bool:
    """Whether `data` opens with a pickle that could run code (see the module docstring)."""
    if not data:
        return False
    protocol_header = data[0] == 0x80
    calls = False
    stream = io.BytesIO(data)
    try:
        for opcode, _argument, _position in pickletools.genops(stream):
            calls = calls or opcode.name in _CODE_OPCODES
            if opcode.name == "STOP":
                return protocol_header or calls
    except (ValueError, struct.error, OverflowError, EOFError):
        # Parsed up to the end of a partial read: the file goes on as a pickle.
        return not complete and stream.tell() >= len(data) and (protocol_header or calls)
    return False


def _npy_objects(head: bytes) -> bool:
    from numpy.lib import format as npy

    stream = io.BytesIO(head)
    try:
        version = npy.read_magic(stream)
        read = npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
        _shape, _fortran, dtype = read(stream)
    except (ValueError, SyntaxError):
        return False  # not a readable .npy: numpy would refuse it too
    return bool(dtype.hasobject)


def _zip_clause(stream, depth: int) -> str | None:
    """What makes a zip archive hold a pickle (its member and why), or None."""
    try:
        with zipfile.ZipFile(stream) as archive:
            members = [info for info in archive.infolist() if not info.is_dir()]
            if any(info.filename == _SB3_VERSION_MEMBER for info in members):
                return "is a stable-baselines3 save, which stores pickles"
            for info in members:
                clause = _member_clause(archive, info, depth)
                if clause is not None:
                    return f"is a zip archive whose member {info.filename} {clause}"
    except (zipfile.BadZipFile, zipfile.LargeZipFile, NotImplementedError, RuntimeError) as exc:
        return f"is a zip archive that cannot be inspected for pickles ({exc})"
    return None


def _member_clause(archive: zipfile.ZipFile, info: zipfile.ZipInfo, depth: int) -> str | None:
    suffix = _pickle_suffix(info.filename)
    if suffix:
        return f"is named like a pickle or torch.save file ({suffix})"
    with archive.open(info) as member:
        head = member.read(HEAD_BYTES)
    if _SB3_SERIALIZED in head:
        return "holds fields pickled by stable-baselines3 (`:serialized:`)"
    clause = _content_clause(head, info.file_size)
    if clause is not None or not head.startswith(_ZIP_MAGIC):
        return clause
    if depth >= ZIP_DEPTH or info.file_size > NESTED_ZIP_BYTES:
        return "is an archive nested too deep or too large to inspect for pickles"
    with archive.open(info) as member:
        return _zip_clause(io.BytesIO(member.read()), depth + 1)


def _local_safetensors(directory: Path, name) -> bool:
    return (
        isinstance(name, str)
        and PurePosixPath(name).name == name
        and name not in ("", ".", "..")
        and name.endswith(".safetensors")
        and (directory / name).is_file()
        and not (directory / name).is_symlink()
    )
