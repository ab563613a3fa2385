"""Signed builds: `joshuac keygen`, `joshuac build --sign`, and install.sh refusing what the robot's key does not sign."""

import os
import stat
import subprocess

import pytest

from testsupport.joshuac_cli import CONFIGS, joshuac

MOCK_ARM = next(path for path in CONFIGS if path.stem == "mock_arm")


def test_keygen_writes_a_private_key_only_its_owner_reads_and_never_overwrites(tmp_path):
    done = joshuac("keygen", str(tmp_path / "release.key"))
    assert done.returncode == 0, done.stderr
    private, public = tmp_path / "release.key", tmp_path / "release.key.pub"
    assert stat.S_IMODE(private.stat().st_mode) == 0o600
    assert public.read_text().startswith("-----BEGIN PUBLIC KEY-----")
    before = private.read_bytes()
    again = joshuac("keygen", str(private))
    assert again.returncode == 1 and "keygen never overwrites a key" in again.stderr
    assert private.read_bytes() == before


def test_a_build_signed_with_a_key_that_is_not_one_is_refused_in_one_line(tmp_path):
    (tmp_path / "not-a-key").write_text("hello\n")
    done = joshuac("build", str(MOCK_ARM), "-o", str(tmp_path / "out"), "--sign", str(tmp_path / "not-a-key"))
    assert done.returncode == 1 and not (tmp_path / "out").exists()
    assert done.stderr.strip().splitlines() == [
        f"joshuac: error: cannot use {tmp_path / 'not-a-key'} as a signing key: it is not a PEM private key "
        "(make one with joshuac keygen)"
    ]


@pytest.fixture(scope="module")
def signed_bundle(tmp_path_factory):
    directory = tmp_path_factory.mktemp("signed")
    assert joshuac("keygen", str(directory / "release.key")).returncode == 0
    done = joshuac(
        "build", str(MOCK_ARM), "-o", str(directory / "out"), "--bundle", "--sign", directory / "release.key"
    )
    assert done.returncode == 0, done.stderr
    return directory


def verify(directory, public) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["openssl", "pkeyutl", "-verify", "-pubin", "-inkey", str(public), "-rawin", "-in", ".joshuac-stamp",
         "-sigfile", ".joshuac-stamp.sig"],
        cwd=directory, capture_output=True, text=True,
    )  # fmt: skip


def test_the_signature_covers_the_stamp_and_openssl_checks_it_without_joshuac(signed_bundle):
    out, public = signed_bundle / "out", signed_bundle / "release.key.pub"
    assert verify(out, public).returncode == 0
    assert ".joshuac-stamp.sig" not in (out / ".joshuac-stamp").read_text()
    again = joshuac("build", str(MOCK_ARM), "-o", str(out), "--bundle", "--check")
    assert again.returncode == 0, again.stdout + again.stderr  # --check compares the files, not the signature


def install(out, key, tmp_path) -> subprocess.CompletedProcess:
    environment = dict(os.environ, JOSHUA_RELEASE_KEY=str(key))
    return subprocess.run(
        ["sh", str(out / "install.sh"), str(tmp_path / "venv")], env=environment, capture_output=True, text=True
    )


@pytest.mark.parametrize(
    ("change", "refusal"),
    [
        (
            "unsigned",
            "the bundle is not signed ({out}/.joshuac-stamp.sig is missing) and this robot requires signed bundles",
        ),
        ("stamp", "the signature {out}/.joshuac-stamp.sig does not match {out}/.joshuac-stamp for the key"),
        ("other key", "the signature {out}/.joshuac-stamp.sig does not match {out}/.joshuac-stamp for the key"),
    ],
)
def test_install_sh_refuses_what_the_robots_key_does_not_sign(signed_bundle, tmp_path, change, refusal):
    out = tmp_path / "out"
    subprocess.run(["cp", "-a", str(signed_bundle / "out"), str(out)], check=True)
    key = signed_bundle / "release.key.pub"
    if change == "unsigned":
        (out / ".joshuac-stamp.sig").unlink()
    elif change == "stamp":  # a file changed and the stamp made again to match: only the signature tells
        with open(out / "nodes/leader.py", "a") as entrypoint:
            entrypoint.write("# changed\n")
        (out / ".joshuac-stamp").write_text(
            subprocess.run(
                ["sh", "-c", "grep '^#' .joshuac-stamp; sed -n 's/^[0-9a-f]\\{64\\}  //p' .joshuac-stamp | xargs sha256sum"],
                cwd=out, capture_output=True, text=True, check=True,
            ).stdout
        )  # fmt: skip
        assert subprocess.run(["sha256sum", "-c", "--quiet", ".joshuac-stamp"], cwd=out).returncode == 0
    else:
        assert joshuac("keygen", str(tmp_path / "other.key")).returncode == 0
        key = tmp_path / "other.key.pub"
    done = install(out, key, tmp_path)
    assert done.returncode == 1
    assert done.stderr.startswith("install.sh: " + refusal.format(out=out)), done.stderr
    assert done.stderr.rstrip().endswith("; nothing installed")
    assert not (tmp_path / "venv").exists()
