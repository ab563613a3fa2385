"""The project's Markdown documents read as GitHub renders them: fenced blocks, heading anchors and links.

The documents are README.md, CONTRIBUTING.md and every page of docs/. A heading's anchor is computed
as GitHub computes it (github-slugger): the heading's text as rendered, in lower case, without
punctuation and symbols, each space a `-`, and `-1`, `-2`... on repeats. Lines inside fenced code
blocks are neither headings nor links.
"""

import re
import unicodedata
from pathlib import Path
from urllib.parse import unquote

ROOT = Path(__file__).resolve().parent.parent
FENCE = re.compile(r"^\s*(`{3,}|~{3,})")
HEADING = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)(?:[ \t]+#+)?[ \t]*$")
CODE_SPAN = re.compile(r"(`+)(.+?)(?<!`)\1(?!`)", re.DOTALL)
LINK_TARGET = re.compile(r"\]\(\s*(<[^>]*>|[^)\s]*)(?:\s+(?:\"[^\"]*\"|'[^']*'))?\s*\)")
INLINE_LINK = re.compile(r"!?\[([^\]]*)\]\([^)]*\)")
HTML_ANCHOR = re.compile(r"<a\s[^>]*\b(?:name|id)=\"([^\"]+)\"", re.IGNORECASE)
HTML_TAG = re.compile(r"<[^>]+>")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def documents(root: Path = ROOT) -> list[Path]:
    """README.md, CONTRIBUTING.md and docs/*.md, in that order."""
    return [root / "README.md", root / "CONTRIBUTING.md", *sorted((root / "docs").glob("*.md"))]


def prose_lines(text: str) -> list[tuple[int, str]]:
    """(line number, line) of every line outside fenced code blocks (fence lines excluded)."""
    kept, fence = [], None
    for number, line in enumerate(text.splitlines(), 1):
        opening = FENCE.match(line)
        if fence is None and opening:
            fence = opening.group(1)
        elif fence is not None:
            if opening and opening.group(1)[0] == fence[0] and len(opening.group(1)) >= len(fence):
                if not line.strip()[len(opening.group(1)) :].strip():
                    fence = None
        else:
            kept.append((number, line))
    return kept


def rendered_heading(text: str) -> str:
    """A heading's text as GitHub shows it: code spans, links and tags reduced to their text."""
    text = CODE_SPAN.sub(lambda match: match.group(2).strip(), text)
    text = INLINE_LINK.sub(lambda match: match.group(1), text)
    return HTML_TAG.sub("", text).strip()


def slug(text: str) -> str:
    """GitHub's anchor of a heading's rendered text (before repeats are numbered)."""
    lowered = text.lower()
    kept = "".join(c for c in lowered if c in " -_" or unicodedata.category(c)[0] in "LNM")
    return kept.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    """Every `#fragment` a link into this document may name: its headings' anchors and HTML anchors."""
    text = path.read_text(encoding="utf-8")
    found: set[str] = set()
    for _, line in prose_lines(text):
        heading = HEADING.match(line)
        if heading:
            base = slug(rendered_heading(heading.group(2)))
            anchor, repeat = base, 0
            while anchor in found:
                repeat += 1
                anchor = f"{base}-{repeat}"
            found.add(anchor)
        found.update(HTML_ANCHOR.findall(line))
    return found


def links(path: Path) -> list[tuple[int, str]]:
    """(line number, target) of every inline link and image outside code, as written."""
    lines = prose_lines(path.read_text(encoding="utf-8"))
    found = []
    paragraph: list[tuple[int, str]] = []
    for number, line in [*lines, (0, "")]:
        if line.strip():
            paragraph.append((number, line))
            continue
        if paragraph:
            text = "\n".join(line for _, line in paragraph)
            without_code = CODE_SPAN.sub(lambda match: " " * len(match.group(0)), text)
            for match in LINK_TARGET.finditer(without_code):
                line_number = paragraph[0][0] + without_code.count("\n", 0, match.start())
                found.append((line_number, match.group(1).strip("<>")))
            paragraph = []
    return found


def broken_links(paths: list[Path], root: Path = ROOT) -> list[str]:
    """`doc:line: target: why` for every relative link or `#anchor` of these documents that does not resolve."""
    problems = []
    anchor_cache: dict[Path, set[str]] = {}
    for path in paths:
        where = path.relative_to(root)
        for line, target in links(path):
            if not target or SCHEME.match(target) or target.startswith("//"):
                continue
            file_part, _, fragment = target.partition("#")
            destination = (path.parent / unquote(file_part)).resolve() if file_part else path.resolve()
            if not destination.is_relative_to(root.resolve()):
                problems.append(f"{where}:{line}: {target}: outside the repository")
            elif not destination.exists():
                problems.append(f"{where}:{line}: {target}: no such file")
            elif fragment and destination.suffix == ".md":
                if destination not in anchor_cache:
                    anchor_cache[destination] = anchors(destination)
                if unquote(fragment) not in anchor_cache[destination]:
                    problems.append(f"{where}:{line}: {target}: no heading with anchor #{fragment}")
    return problems
