"""check, build and fmt read only regular files up to 1 MiB, and fmt never rewrites what it cannot read faithfully."""

import os
import subprocess

import pytest

from joshua_codegen.diagnostics import Diagnostic, format_text
from joshua_codegen.source_file import MAX_DESCRIPTION_BYTES
from testsupport.joshuac_cli import CONFIGS, JOSHUAC, ROOT

pytestmark = pytest.mark.process  # joshuac's command line

COMMANDS = [("check",), ("build", "-o", "out"), ("fmt",), ("fmt", "--write"), ("fmt", "--check")]
# Generous: a hang fails the test instead of blocking the suite; the refusal itself takes well under 1 s.
HANG_TIMEOUT_S = 20


def run(*args, cwd):
    return subprocess.run([*JOSHUAC, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=HANG_TIMEOUT_S)


@pytest.mark.parametrize("command", COMMANDS, ids=" ".join)
def test_a_fifo_is_refused_without_blocking(command, tmp_path):
    os.mkfifo(tmp_path / "robot.pbtxt")
    result = run(*command[:1], "robot.pbtxt", *command[1:], cwd=tmp_path)
    assert result.returncode == 1
    assert (
        "robot.pbtxt:1:1: error[E009]: the path is a FIFO (named pipe), not a regular file"
        in result.stderr + result.stdout
    )
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("path", ["/dev/urandom", "/dev/zero", "/proc/self/status", "/proc/self/environ"])
def test_devices_and_proc_files_are_refused(path, tmp_path):
    result = run("check", path, cwd=tmp_path)
    assert result.returncode == 1
    assert f"{path}:1:1: error[E009]: " in result.stdout


@pytest.mark.parametrize("command", COMMANDS, ids=" ".join)
def test_a_file_over_the_size_limit_is_refused_before_reading(command, tmp_path):
    big = tmp_path / "robot.pbtxt"
    with open(big, "wb") as handle:
        handle.truncate(MAX_DESCRIPTION_BYTES + 1)  # sparse: costs no disk
    result = run(*command[:1], "robot.pbtxt", *command[1:], cwd=tmp_path)
    assert result.returncode == 1
    assert f"error[E009]: the file is too large ({MAX_DESCRIPTION_BYTES + 1} bytes)" in result.stderr + result.stdout
    assert os.path.getsize(big) == MAX_DESCRIPTION_BYTES + 1


@pytest.mark.parametrize(
    "content",
    [
        b'robot_config {\n  name: "bras"\n  # articul\xe9\n}\n',  # Latin-1
        b'robot_config {\n  name: "a\0b"\n}\n',  # NUL
        b'robot_config {\n  name: "x"  \xff\xfe\n}\n',
    ],
    ids=["latin1", "nul", "invalid-utf8"],
)
def test_fmt_write_refuses_text_it_cannot_read_faithfully_and_leaves_it_byte_for_byte(content, tmp_path):
    path = tmp_path / "robot.pbtxt"
    path.write_bytes(content)
    result = run("fmt", "--write", "robot.pbtxt", cwd=tmp_path)
    assert result.returncode == 1
    assert "error[E008]" in result.stderr
    assert path.read_bytes() == content
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.pbtxt"]


def test_fmt_check_takes_several_files_and_names_each_unformatted_one(tmp_path):
    formatted = [str(config) for config in CONFIGS]
    assert run("fmt", "--check", *formatted, cwd=tmp_path).returncode == 0
    messy = tmp_path / "messy.pbtxt"
    messy.write_text(CONFIGS[0].read_text().replace("\n  ", "\n     ", 3))
    result = run("fmt", "--check", *formatted, messy, cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr.count("is not formatted") == 1 and "messy.pbtxt" in result.stderr
    printing = run("fmt", *formatted[:2], cwd=tmp_path)
    assert printing.returncode == 2 and "printing takes one file" in printing.stderr


def test_fmt_write_through_a_symbolic_link_rewrites_the_file_and_keeps_the_link(tmp_path):
    real = tmp_path / "real.pbtxt"
    real.write_text(CONFIGS[0].read_text().replace("\n  ", "\n     ", 3))
    os.chmod(real, 0o640)
    (tmp_path / "link.pbtxt").symlink_to(real)
    assert run("fmt", "--write", "link.pbtxt", cwd=tmp_path).returncode == 0
    assert (tmp_path / "link.pbtxt").is_symlink()
    assert real.read_text() == CONFIGS[0].read_text()
    assert real.stat().st_mode & 0o777 == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.pbtxt", "real.pbtxt"]


class CountingSource(str):
    """A source text that counts how often it is split into lines."""

    splits = 0

    def split(self, *args, **kwargs):
        CountingSource.splits += 1
        return super().split(*args, **kwargs)


def test_text_diagnostics_split_each_source_once_however_many_there_are():
    source = CountingSource("".join(f"line {n}\n" for n in range(2000)))
    diagnostics = [Diagnostic("robot.pbtxt", n, 1, "E003", "error", "bad") for n in range(1, 2001)]
    text = format_text(diagnostics, {"robot.pbtxt": source})
    assert text.count("error[E003]") == 2000 and "line 1999\n^" in text
    assert CountingSource.splits == 1


def test_the_documented_limit_is_the_enforced_one():
    assert MAX_DESCRIPTION_BYTES == 1024 * 1024
    assert "at most 1 MiB\n(1048576 bytes" in (ROOT / "docs" / "description-language.md").read_text()
