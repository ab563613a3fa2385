"""The compiled form of the supervisor's code module, byte for byte the same on every build of the same code.

A hash-based pyc (PEP 552) that Python checks against the source's hash: no timestamp in it, and an edited
module is compiled anew instead of trusted. The code is marshalled in format 2, which writes no back-references
(whose choice depends on reference counts in the compiling process), and holds no frozenset constant (whose
order depends on the hash seed). Compiled once per code, kept beside the compiled templates.
"""

import hashlib
import importlib.util
import marshal
import os
import tempfile
from functools import cache
from pathlib import Path

from joshua_codegen.render import TEMPLATE_CACHE_DIR

MARSHAL_VERSION = 2  # the last format without back-references
CHECKED_HASH_FLAGS = 0b11  # a hash-based pyc whose source hash Python checks at import


def cached_path(source: bytes) -> Path:
    key = hashlib.sha256(importlib.util.MAGIC_NUMBER + source).hexdigest()
    return TEMPLATE_CACHE_DIR / f"supervisor-{key}.pyc"


def frozen_sets(code) -> list[frozenset]:
    found = []
    for constant in code.co_consts:
        if isinstance(constant, frozenset):
            found.append(constant)
        elif hasattr(constant, "co_consts"):
            found += frozen_sets(constant)
    return found


def compiled(source: bytes, filename: str) -> bytes:
    code = compile(source, filename, "exec", dont_inherit=True)
    if frozen_sets(code):
        raise ValueError(f"{filename} compiles to a set constant, whose order depends on the hash seed: use a tuple")
    header = importlib.util.MAGIC_NUMBER + CHECKED_HASH_FLAGS.to_bytes(4, "little")
    return header + importlib.util.source_hash(source) + marshal.dumps(code, MARSHAL_VERSION)


def write_cached(path: Path, data: bytes) -> None:
    """Best effort, replaced by rename: a read-only install compiles on every build instead."""
    try:
        path.parent.mkdir(exist_ok=True)
        descriptor, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(descriptor, "wb") as stream:
            stream.write(data)
        os.replace(temporary, path)
    except OSError:
        try:
            os.unlink(temporary)
        except OSError:
            pass


@cache
def pyc(source: bytes, filename: str) -> bytes:
    """The pyc of `source` for this interpreter, from the cache when an entry of the same source is there."""
    path = cached_path(source)
    try:
        data = path.read_bytes()
    except OSError:
        data = b""
    if data[8:16] == importlib.util.source_hash(source) and data[:4] == importlib.util.MAGIC_NUMBER:
        return data
    data = compiled(source, filename)
    write_cached(path, data)
    return data


def cache_path(module: str) -> str:
    """Where Python looks for the compiled form of `module`, relative to the module's directory."""
    return os.path.relpath(importlib.util.cache_from_source(module), ".")
