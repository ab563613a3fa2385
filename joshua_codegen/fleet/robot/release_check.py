"""Checking a release before anything of it runs: the archive's members, the stamp's signature, every file."""

import hashlib
import os
import shutil
import stat
import subprocess
import tarfile

from layout import COMMAND_TIMEOUT_S, ENVIRONMENT_DIR, RELEASE_DIGITS, SIGNATURE, STAMP, Refused


def safe_members(archive: tarfile.TarFile) -> list[tarfile.TarInfo]:
    """The archive's members when every one is a regular file or directory inside it, else Refused."""
    members = archive.getmembers()
    for member in members:
        name = member.name
        parts = [part for part in name.split("/") if part not in ("", ".")]
        if name.startswith("/") or ".." in parts or not (member.isfile() or member.isdir()):
            raise Refused(f"the release archive holds {name!r}, which is not a file or directory inside it")
        member.mode = 0o755 if member.isdir() or member.mode & 0o111 else 0o644
        member.uid = member.gid = 0
        member.uname = member.gname = ""
    return members


def file_hash(path: str) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def read_stamp(directory: str) -> dict[str, str]:
    """{path: sha256} of a release's stamp (sha256sum's format after `#` comment lines)."""
    listed = {}
    with open(os.path.join(directory, STAMP), encoding="utf-8") as stamp:
        for line in stamp:
            line = line.rstrip("\n")
            if line.startswith("#") or not line:
                continue
            digest, separator, name = line.partition("  ")
            if not separator or len(digest) != 64:
                raise Refused(f"{STAMP} has a line that is not `SHA256  PATH`")
            listed[name] = digest
    return listed


def check_signature(directory: str, key: str) -> None:
    signature = os.path.join(directory, SIGNATURE)
    if not os.path.isfile(signature):
        raise Refused(
            f"the release is not signed ({SIGNATURE} is missing) and this robot requires signed releases ({key})"
        )
    if shutil.which("openssl") is None:
        raise Refused("openssl is needed to check the release's signature and is not installed")
    command = ["openssl", "pkeyutl", "-verify", "-pubin", "-inkey", key, "-rawin"]
    command += ["-in", os.path.join(directory, STAMP), "-sigfile", signature]
    done = subprocess.run(command, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if done.returncode != 0:
        raise Refused(
            f"the signature {SIGNATURE} does not match {STAMP} for the key {key}: the stamp was changed or signed by another key"
        )


def check_release(directory: str, release: str, key: str) -> None:
    """Refused, naming the file, unless `directory` holds exactly the files its stamp lists, unchanged."""
    if not os.path.isfile(os.path.join(directory, STAMP)):
        raise Refused(f"the release has no {STAMP}")
    if file_hash(os.path.join(directory, STAMP))[:RELEASE_DIGITS] != release:
        raise Refused(f"{STAMP} is not the stamp of release {release}")
    if os.path.exists(key):
        check_signature(directory, key)
    listed = read_stamp(directory)
    for name, digest in sorted(listed.items()):
        path = os.path.join(directory, name)
        if os.path.islink(path) or not os.path.isfile(path):
            raise Refused(f"{name} is missing from the release")
        if file_hash(path) != digest:
            raise Refused(f"{name} differs from the release's {STAMP}" + (" (signed)" if os.path.exists(key) else ""))
    parents = set()
    for name in listed:
        parent = os.path.dirname(name)
        while parent:
            parents.add(parent)
            parent = os.path.dirname(parent)
    for base, directories, files in os.walk(directory):
        relative = os.path.relpath(base, directory)
        if relative == ".":
            directories[:] = [name for name in directories if name != ENVIRONMENT_DIR]
        for name in sorted(directories + files):
            entry = os.path.normpath(os.path.join(relative, name))
            mode = os.lstat(os.path.join(base, name)).st_mode
            if stat.S_ISDIR(mode) and entry in parents:
                continue
            if entry not in listed and entry not in (STAMP, SIGNATURE):
                raise Refused(f"{entry} is not part of the release (not in its {STAMP})")
