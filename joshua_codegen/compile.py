"""The whole compiler as one pure function: description text in, diagnostics and files out."""

from dataclasses import dataclass

from joshua_codegen.check import CheckResult, check_file
from joshua_codegen.plan import plan
from joshua_codegen.render import render


@dataclass
class Compilation:
    check: CheckResult
    files: dict[str, str] | None  # None when the description has errors

    @property
    def robot_name(self) -> str | None:
        description = self.check.description
        return description.robot_config.name if description is not None else None


def compile_file(path: str, overrides=(), prefix: str | None = None) -> Compilation:
    """Check a description and, when it has no error, render every output file."""
    result = check_file(path, overrides)
    if result.has_errors or result.description is None:
        return Compilation(result, None)
    return Compilation(result, render(plan(result.description, path), prefix))
