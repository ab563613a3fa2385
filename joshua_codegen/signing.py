"""Release signatures: `joshuac keygen KEY` makes an Ed25519 key pair, `joshuac build --sign KEY` signs the stamp.

The signature (`.joshuac-stamp.sig`, next to the stamp, 64 raw bytes) is Ed25519 over the stamp file's
bytes, so it covers every file the stamp lists. Robots check it with OpenSSL 3, without joshuac:

    openssl pkeyutl -verify -pubin -inkey KEY.pub -rawin -in .joshuac-stamp -sigfile .joshuac-stamp.sig

The private key is PKCS#8 PEM, unencrypted, mode 0600; the public key SubjectPublicKeyInfo PEM. Ed25519
signatures are deterministic: the same stamp and key give the same signature on every build.
"""

import os
import stat
from collections.abc import Callable
from pathlib import Path

PUBLIC_SUFFIX = ".pub"
DEFAULT_RELEASE_KEY = "/etc/joshua/release.pub"  # where robots keep the public key (install.sh, fleet_config)
PRIVATE_MODE = 0o600
PUBLIC_MODE = 0o644
MAX_KEY_BYTES = 64 * 1024  # a PEM key is a few hundred bytes


class SigningError(Exception):
    """A key cannot be made or used; the message says why in one line."""


def public_path(private: Path) -> Path:
    """Where keygen puts the public key of `private`: the same path with `.pub` added."""
    return private.with_name(private.name + PUBLIC_SUFFIX)


def generate_key_pair(private: Path) -> Path:
    """Write a new private key at `private` (0600) and its public key beside it; return the public key's path.
    Existing files are never overwritten."""
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

    public = public_path(private)
    for path in (private, public):
        if os.path.lexists(path):
            raise SigningError(f"{path} exists; keygen never overwrites a key: choose another path or remove it")
    key = Ed25519PrivateKey.generate()
    private_pem = key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )
    public_pem = key.public_key().public_bytes(
        serialization.Encoding.PEM, serialization.PublicFormat.SubjectPublicKeyInfo
    )
    _write_new(private, private_pem, PRIVATE_MODE)
    try:
        _write_new(public, public_pem, PUBLIC_MODE)
    except SigningError:
        os.unlink(private)
        raise
    return public


def _write_new(path: Path, data: bytes, mode: int) -> None:
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, mode)
    except OSError as exc:
        raise SigningError(f"cannot create {path}: {exc.strerror or exc}") from None
    with os.fdopen(fd, "wb") as file:
        file.write(data)
    os.chmod(path, mode)


def load_signer(private: Path) -> Callable[[bytes], bytes]:
    """A function signing bytes with the Ed25519 private key at `private`."""
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

    try:
        status = os.stat(private)
        if not stat.S_ISREG(status.st_mode) or status.st_size > MAX_KEY_BYTES:
            raise SigningError(f"{private} is not a key file (a regular file of at most {MAX_KEY_BYTES} bytes)")
        data = Path(private).read_bytes()
    except OSError as exc:
        raise SigningError(f"cannot read the signing key {private}: {exc.strerror or exc}") from None
    try:
        key = serialization.load_pem_private_key(data, password=None)
    except (ValueError, TypeError) as exc:
        reason = "it is encrypted" if isinstance(exc, TypeError) else "it is not a PEM private key"
        raise SigningError(f"cannot use {private} as a signing key: {reason} (make one with joshuac keygen)") from None
    if not isinstance(key, Ed25519PrivateKey):
        raise SigningError(f"{private} is not an Ed25519 key (make one with joshuac keygen)")
    return key.sign
