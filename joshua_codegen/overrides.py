"""`--set KEY=VALUE` overrides, applied to a copy of a loaded description before the rules run.

Keys: a robot field (`mode`, `name`, `ros_domain_id`), a field of a robot block
(`shutdown.sigint_grace_s`, `simulation.model`), a field of a host addressed by its name
(`host.gpu.address`), an environment entry (`env.NAME`), or a node field addressed by the node's
name (`NODE_NAME.qos_depth`, `NODE_NAME.env.NAME`). Values are
parsed per field type; a repeated field takes a list that replaces the whole list, comma-separated
(`device_ids=1,2,3`) or bracketed as in a description (`device_ids=[1, 2, 3]`, `input_topics=["/a", "/b"]`).
Problems are diagnostics at path `--set`, line = the override's 1-based position.
"""

from __future__ import annotations

from collections.abc import Sequence

from google.protobuf.descriptor import FieldDescriptor

from joshua_codegen import defaults
from joshua_codegen.diagnostics import ERROR, Diagnostic
from joshua_codegen.positions import Location, Path, SourceMap
from joshua_codegen.syntax import ListValue, Scalar, SyntaxProblem, Token, parse_syntax
from joshua_codegen.values import ValueProblem, parse_enum, parse_scalar, suggest
from joshua_core.schema import RobotConfig, RobotDescription

OVERRIDE_PATH = "--set"
MALFORMED_OVERRIDE = "E010"
UNKNOWN_OVERRIDE_TARGET = "E011"
INVALID_OVERRIDE_VALUE = "E012"
# How many node names an "unknown node" message lists.
LISTED_NODE_NAMES = 8


class OverrideProblem(Exception):
    def __init__(self, code: str, message: str):
        super().__init__(message)
        self.code = code
        self.message = message


def _value(fd: FieldDescriptor, text: str):
    if fd.type == FieldDescriptor.TYPE_STRING:
        return text
    if fd.type == FieldDescriptor.TYPE_ENUM:
        number, reason = parse_enum(fd, text)
        if number is None:
            raise OverrideProblem(INVALID_OVERRIDE_VALUE, reason)
        return number
    try:
        return parse_scalar(fd, Scalar([Token(text, 1, 1)]))
    except ValueProblem as problem:
        raise OverrideProblem(INVALID_OVERRIDE_VALUE, str(problem)) from None


def _list_item(fd: FieldDescriptor, item: Scalar):
    """One item of a bracketed list, read as in a description (strings may be quoted or bare)."""
    if fd.type == FieldDescriptor.TYPE_STRING and not item.is_string:
        return item.first.text
    if fd.type == FieldDescriptor.TYPE_ENUM:
        return _value(fd, item.first.text)
    try:
        return parse_scalar(fd, item)
    except ValueProblem as problem:
        raise OverrideProblem(INVALID_OVERRIDE_VALUE, str(problem)) from None


def _list(fd: FieldDescriptor, text: str) -> list:
    """A repeated field's new values: `1,2,3` (comma-separated) or `[1, 2, 3]` / `["a", "b"]` (as in a description)."""
    stripped = text.strip()
    if not stripped.startswith("["):
        return [_value(fd, item.strip()) for item in text.split(",")] if stripped else []
    try:
        document = parse_syntax(f"{fd.name}: {stripped}")
    except SyntaxProblem as problem:
        message = problem.message.replace("end of file", "end of the value")
        raise OverrideProblem(INVALID_OVERRIDE_VALUE, f"{fd.name}: {message}") from None
    value = document.fields[0].value if len(document.fields) == 1 else None
    if not isinstance(value, ListValue) or any(not isinstance(item, Scalar) for item in value.items):
        raise OverrideProblem(INVALID_OVERRIDE_VALUE, f"{fd.name} takes a list of values: [1, 2, 3] or 1,2,3")
    return [_list_item(fd, item) for item in value.items]


def _assign(message, fd: FieldDescriptor, text: str) -> None:
    if fd.is_repeated:
        values = _list(fd, text)
        container = getattr(message, fd.name)
        del container[:]
        container.extend(values)
    else:
        setattr(message, fd.name, _value(fd, text))


def _field(message, name: str, owner: str):
    fd = message.DESCRIPTOR.fields_by_name.get(name)
    if fd is None:
        hint = suggest(name, message.DESCRIPTOR.fields_by_name)
        text = f'{owner} has no field "{name}"'
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, text + (f'; did you mean "{hint}"?' if hint else ""))
    return fd


def _set_in(message, segments: list[str], text: str, path: Path, owner: str) -> Path:
    """Set `segments` (a field, `block.field` or `env.NAME`) of `message`; return the path set."""
    fd = _field(message, segments[0], owner)
    path = path + (fd.name,)
    if fd.message_type is not None and fd.message_type.GetOptions().map_entry:
        if len(segments) != 2:
            raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, f"set one variable: {'.'.join(path[1:])}.NAME=VALUE")
        getattr(message, fd.name)[segments[1]] = text
        return path + (segments[1],)
    if fd.message_type is not None:
        if fd.name == "node":
            raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, "address a node by its name: NODE_NAME.FIELD=VALUE")
        if fd.is_repeated and "name" in fd.message_type.fields_by_name:
            return _set_in_named(getattr(message, fd.name), fd.name, segments[1:], text, path)
        if len(segments) < 2:
            example = next(iter(fd.message_type.fields_by_name))
            raise OverrideProblem(
                UNKNOWN_OVERRIDE_TARGET, f"{fd.name} is a block: set one of its fields, e.g. {fd.name}.{example}=..."
            )
        return _set_in(getattr(message, fd.name), segments[1:], text, path, fd.name)
    if len(segments) > 1:
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, f'{fd.name} is a value and has no field "{segments[1]}"')
    _assign(message, fd, text)
    return path


def _set_in_named(container, block: str, segments: list[str], text: str, path: Path) -> Path:
    """Set a field of the element of a repeated block named `segments[0]` (`host.gpu.address`)."""
    if len(segments) < 2:
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, f"address a {block} by its name: {block}.NAME.FIELD=VALUE")
    matches = [index for index, element in enumerate(container) if element.name == segments[0]]
    if len(matches) != 1:
        names = ", ".join(element.name for element in container) or "none"
        problem = f'no {block} named "{segments[0]}" ({block}s: {names})'
        raise OverrideProblem(
            UNKNOWN_OVERRIDE_TARGET, problem if not matches else f'{len(matches)} {block}s are named "{segments[0]}"'
        )
    index = matches[0]
    return _set_in(container[index], segments[1:], text, path + (index,), f'{block} "{segments[0]}"')


def _closest_target(name: str, node_names: list[str]) -> str | None:
    """A node name containing `name`, else the closest node name, else the closest robot field."""
    containing = [candidate for candidate in node_names if name in candidate]
    if containing:
        return containing[0]
    return suggest(name, node_names) or suggest(name, RobotConfig.DESCRIPTOR.fields_by_name)


def _apply(config: RobotConfig, key: str, text: str) -> Path:
    segments = key.split(".")
    if any(not segment for segment in segments):
        raise OverrideProblem(MALFORMED_OVERRIDE, f'key "{key}" has an empty part; expected names joined by "."')
    if segments[0] in RobotConfig.DESCRIPTOR.fields_by_name:
        return _set_in(config, segments, text, ("robot_config",), "robot_config")
    names = defaults.node_names(config)
    matches = [i for i, name in enumerate(names) if name == segments[0]]
    if not matches:
        hint = _closest_target(segments[0], names)
        listed = ", ".join(names[:LISTED_NODE_NAMES]) + (", ..." if len(names) > LISTED_NODE_NAMES else "")
        message = f'no robot field or node named "{segments[0]}"'
        message += f'; did you mean "{hint}"?' if hint else f" (nodes: {listed or 'none'})"
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, message)
    if len(matches) > 1:
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, f'{len(matches)} nodes are named "{segments[0]}"')
    if len(segments) < 2:
        raise OverrideProblem(UNKNOWN_OVERRIDE_TARGET, f"name a field of the node: {segments[0]}.FIELD=VALUE")
    index = matches[0]
    return _set_in(config.node[index], segments[1:], text, ("robot_config", "node", index), f'node "{segments[0]}"')


def apply_overrides(
    description: RobotDescription, source: SourceMap, overrides: Sequence[str]
) -> tuple[RobotDescription, SourceMap, list[Diagnostic]]:
    """A new description with the overrides applied (the input is left untouched)."""
    result = RobotDescription()
    result.CopyFrom(description)
    diagnostics = []
    for line, override in enumerate(overrides, start=1):
        end = len(override) + 1
        key, equals, text = override.partition("=")
        try:
            if not equals or not key.strip():
                raise OverrideProblem(
                    MALFORMED_OVERRIDE, f'expected KEY=VALUE (e.g. mode=MODE_SIMULATION), got "{override}"'
                )
            trial = RobotConfig()
            trial.CopyFrom(result.robot_config)
            path = _apply(trial, key.strip(), text)
        except OverrideProblem as problem:
            diagnostics.append(Diagnostic(OVERRIDE_PATH, line, 1, problem.code, ERROR, problem.message, line, end))
            continue
        result.robot_config.CopyFrom(trial)
        source = source.replaced(path, Location(OVERRIDE_PATH, line, 1, line, end))
    return result, source, diagnostics
