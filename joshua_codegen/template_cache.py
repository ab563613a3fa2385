"""Compiled Jinja2 templates kept in the package directory, written only where that directory is writable."""

import os
import tempfile
from pathlib import Path

import jinja2


class PackageBytecodeCache(jinja2.BytecodeCache):
    """Jinja2's bytecode cache in one directory of the package, shared by every user of the install.

    Jinja2 stores each template's source checksum with its code and ignores an entry whose checksum
    differs, so an entry left from older templates is recompiled, never misused. Writing is best
    effort: a read-only install still builds, only without the saving. Entries are replaced by rename,
    so concurrent builds never read half an entry.
    """

    def __init__(self, directory: Path):
        self.directory = Path(directory)

    def _path(self, bucket: jinja2.bccache.Bucket) -> Path:
        return self.directory / f"{bucket.key}.cache"

    def load_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        try:
            with open(self._path(bucket), "rb") as stream:
                bucket.load_bytecode(stream)
        except OSError:
            pass

    def dump_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        try:
            self.directory.mkdir(exist_ok=True)
            descriptor, temporary = tempfile.mkstemp(dir=self.directory, suffix=".tmp")
        except OSError:
            return
        try:
            with os.fdopen(descriptor, "wb") as stream:
                bucket.write_bytecode(stream)
            os.replace(temporary, self._path(bucket))
        except OSError:
            try:
                os.unlink(temporary)
            except OSError:
                pass
