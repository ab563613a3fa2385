"""Values too long for exec(2) or systemd are refused by `check`, with the limits the kernel and systemd really have."""

import errno
import subprocess

import pytest

from joshua_codegen.check import check_text
from joshua_codegen.rules.e118_command_too_long import LONG_LINE_MAX, MAX_ARG_STRLEN
from testsupport.joshuac_cli import ROOT, joshuac


def custom(args: list[str]) -> str:
    listed = ", ".join(f'"{arg}"' for arg in args)
    return f"""robot_config {{
  name: "limits"
  mode: MODE_TELEOPERATION
  node {{
    name: "tool"
    type: CUSTOM
    executable: "/usr/bin/tool"
    args: [{listed}]
  }}
}}
"""


def codes(text: str, prefix: str | None = None) -> list[tuple[str, int, int]]:
    return [(d.code, d.line, d.column) for d in check_text("r.pbtxt", text, prefix=prefix).diagnostics]


@pytest.mark.process
def test_the_argument_limit_is_the_kernels():
    subprocess.run(["/bin/true", "a" * (MAX_ARG_STRLEN - 1)], check=True)
    with pytest.raises(OSError) as refused:
        subprocess.run(["/bin/true", "a" * MAX_ARG_STRLEN])
    assert refused.value.errno == errno.E2BIG


@pytest.mark.process
def test_the_line_limit_is_systemds(tmp_path):
    def verify(length: int) -> str:
        head = "ExecStart=/bin/true "
        unit = tmp_path / "limit.service"
        unit.write_text(f"[Unit]\nDescription=x\n[Service]\nType=exec\n{head}{'a' * (length - len(head))}\n")
        result = subprocess.run(["systemd-analyze", "verify", str(unit)], capture_output=True, text=True)
        return result.stdout + result.stderr

    assert "No buffer space" not in verify(LONG_LINE_MAX - 1)
    assert "No buffer space" in verify(LONG_LINE_MAX)


def test_one_argument_over_the_exec_limit_is_an_error_at_its_position():
    assert codes(custom(["a" * (MAX_ARG_STRLEN - 100)])) == []
    assert codes(custom(["-v", "a" * MAX_ARG_STRLEN])) == [("E118", 8, 18)]


def test_arguments_that_together_exceed_the_budget_are_an_error():
    assert codes(custom(["a" * 120_000] * 9)) == [("E118", 8, 12)]


def test_quoting_that_makes_a_unit_line_too_long_is_an_error():
    quotes = '\\"' * 100_000  # 100000 quote characters each: 800 kB of arguments, 1.6 MB once systemd-quoted
    assert codes(custom([quotes] * 8)) == [("E118", 8, 12)]


@pytest.mark.process
def test_build_refuses_before_writing(tmp_path):
    description = tmp_path / "robot.pbtxt"
    description.write_text(custom(["a" * MAX_ARG_STRLEN]))
    result = joshuac("build", description, "-o", tmp_path / "out")
    assert result.returncode == 1
    assert "error[E118]" in result.stderr and "(E2BIG)" in result.stderr
    assert not (tmp_path / "out").exists()


def test_option_like_programs_are_refused():
    text = (ROOT / "config/robots/mock_arm.pbtxt").read_text()
    result = check_text("r.pbtxt", text, ["python_executable=--version"])
    assert [d.code for d in result.diagnostics if d.is_error] == ["E117"]
