"""web/src/types.ts, the page's TypeScript types, rendered from the API's schema document (api.schema.json).

    python -m joshua_runtime.dashboard.api_typescript          # rewrite web/src/types.ts (make api-types)
    python -m joshua_runtime.dashboard.api_typescript --check  # exit 1 when web/src/types.ts is stale
    python -m joshua_runtime.dashboard.api_typescript --if-changed  # rewrite it only when stale (set-up)

It renders the JSON Schema the document uses, no more: enumerations of strings, objects with
properties (an `allOf` of references becomes `extends`), maps (additionalProperties), arrays, references
and unions of types (`anyOf`, a list of types). Anything else is an error, so the schema cannot say what the page's types miss.
"""

import sys
from pathlib import Path

from joshua_runtime.dashboard.api_schema import SCHEMA, SCHEMA_PATH

ROOT = Path(__file__).resolve().parents[3]
TYPES_PATH = ROOT / "web" / "src" / "types.ts"
REFERENCE_PREFIX = "#/$defs/"
PRIMITIVES = {"string": "string", "number": "number", "integer": "number", "boolean": "boolean", "null": "null"}
# The keywords that say nothing of the type (validation only, or prose).
IGNORED_KEYWORDS = {"description", "required", "additionalProperties", "unevaluatedProperties"}


class UnsupportedSchema(ValueError):
    """A construct of the schema this renderer does not turn into TypeScript."""


def render(schema: dict) -> str:
    """The text of types.ts for `schema`."""
    source = SCHEMA_PATH.relative_to(ROOT)
    lines = [
        f"// The JSON shapes of the dashboard's and the fleet view's API, rendered from {source}",
        "// by `make api-types` (runtime/joshua_runtime/dashboard/api_typescript.py): do not edit.",
        "",
        "/** The version of the API these types describe (MAJOR.MINOR, see the schema's description). */",
        f'export const API_VERSION = "{schema["version"]}";',
    ]
    for name, definition in schema["$defs"].items():
        lines += ["", *_declaration(name, definition)]
    lines += ["", "/** The data of each event of /api/events, by its name. */", "export interface ServerEvents {"]
    lines += [f"  {kind}: {_type(reference)};" for kind, reference in schema["events"].items()]
    lines += ["}", ""]
    return "\n".join(lines)


def _comment(definition: dict, indent: str = "") -> list[str]:
    text = definition.get("description")
    return [f"{indent}/** {text} */"] if text else []


def _declaration(name: str, definition: dict) -> list[str]:
    if "properties" in definition:
        bases = [_reference_name(part) for part in definition.get("allOf", [])]
        extends = f" extends {', '.join(bases)}" if bases else ""
        required = set(definition.get("required", ()))
        members = []
        for key, member in definition["properties"].items():
            members += _comment(member, "  ") + [f"  {key}{'' if key in required else '?'}: {_type(member)};"]
        return _comment(definition) + [f"export interface {name}{extends} {{", *members, "}"]
    if set(definition) - IGNORED_KEYWORDS == {"allOf"}:
        return _comment(definition) + [f"export type {name} = {' & '.join(map(_type, definition['allOf']))};"]
    return _comment(definition) + [f"export type {name} = {_type(definition)};"]


def _reference_name(schema: dict) -> str:
    reference = schema.get("$ref", "")
    if not reference.startswith(REFERENCE_PREFIX) or len(schema) != 1:
        raise UnsupportedSchema(f"expected a reference to {REFERENCE_PREFIX}NAME, found {schema}")
    return reference.removeprefix(REFERENCE_PREFIX)


def _type(schema: dict) -> str:
    """The TypeScript type of `schema` (a reference, an enumeration, or a type with its items)."""
    if "$ref" in schema:
        return _reference_name(schema)
    if "enum" in schema:
        return " | ".join(f'"{value}"' for value in schema["enum"])
    if "anyOf" in schema:
        return " | ".join(_type(option) for option in schema["anyOf"])
    types = schema.get("type")
    if isinstance(types, list):
        return " | ".join(_type({**schema, "type": one}) for one in types)
    if types in PRIMITIVES:
        return PRIMITIVES[types]
    if types == "array":
        item = _type(schema["items"])
        return f"({item})[]" if " " in item else f"{item}[]"
    if types == "object" and isinstance(schema.get("additionalProperties"), dict) and "properties" not in schema:
        return f"Record<string, {_type(schema['additionalProperties'])}>"
    raise UnsupportedSchema(f"no TypeScript type for {schema}")


def main(argv: list[str] | None = None) -> int:
    options = set(sys.argv[1:] if argv is None else argv)
    text = render(SCHEMA)
    stale = not TYPES_PATH.is_file() or TYPES_PATH.read_text(encoding="utf-8") != text
    if "--check" in options:
        if stale:
            print(f"{TYPES_PATH} is stale: run `make api-types`", file=sys.stderr)
        return 1 if stale else 0
    if stale or "--if-changed" not in options:
        TYPES_PATH.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
