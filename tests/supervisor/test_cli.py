"""The supervisor's options: a start without arguments gets what the parser gives, without the parser."""

import subprocess
import sys

from joshua_codegen.supervisor.cli import option_table, parse_arguments


def test_the_defaults_of_a_start_without_arguments_are_the_parsers():
    without = vars(parse_arguments([]))
    parsed = vars(parse_arguments(["--python", without["python"]]))  # one option, given its default: argparse runs
    assert without == parsed
    assert sorted(without) == sorted(flag[2:].replace("-", "_") for flag, _ in option_table())


def test_a_start_without_arguments_does_not_import_argparse():
    program = (
        "import sys\n"
        "from joshua_codegen.supervisor.cli import parse_arguments\n"
        "parse_arguments([])\n"
        "print('argparse' in sys.modules, 'shutil' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=60, check=True)
    assert result.stdout.split() == ["False", "False"]
