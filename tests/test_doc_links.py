"""Every relative link and `#anchor` of README.md, CONTRIBUTING.md and docs/*.md resolves, as GitHub resolves it,
and the README stays a newcomer's page that leads to every page of docs/.

Anchors are computed as GitHub computes them (testsupport/documents.py); links to other sites are
not followed (nothing is fetched).
"""

import pytest

from testsupport.documents import ROOT, anchors, broken_links, documents, links, slug

README_MAX_LINES = 250  # what it is, the two commands, a first robot, where to go next; the rest is in docs/

# (heading as written, its anchor on GitHub)
GITHUB_ANCHORS = [
    ("A running robot: `joshuac run --watch`", "a-running-robot-joshuac-run---watch"),
    ("The dashboard and the fleet view", "the-dashboard-and-the-fleet-view"),
    ("Node types (`core/joshua_core/node_types.py`)", "node-types-corejoshua_corenode_typespy"),
    ("SIGINT → SIGTERM → SIGKILL", "sigint--sigterm--sigkill"),
    ("Settings, v4!", "settings-v4"),
]


def test_the_documents_exist():
    assert (ROOT / "README.md").is_file() and (ROOT / "CONTRIBUTING.md").is_file()
    assert (ROOT / "docs" / "architecture.md").is_file()


def test_the_readme_is_a_short_page_that_leads_to_every_page_of_docs():
    readme = ROOT / "README.md"
    assert len(readme.read_text(encoding="utf-8").splitlines()) <= README_MAX_LINES
    linked = {(readme.parent / target.partition("#")[0]).resolve() for _, target in links(readme)}
    unlinked = [path.name for path in sorted((ROOT / "docs").glob("*.md")) if path.resolve() not in linked]
    assert unlinked == [], "pages of docs/ the README does not link to"


def test_every_relative_link_and_anchor_resolves():
    assert broken_links([path for path in documents() if path.exists()]) == []


@pytest.mark.parametrize(("heading", "anchor"), GITHUB_ANCHORS)
def test_anchors_are_computed_as_github_does(heading, anchor, tmp_path):
    page = tmp_path / "page.md"
    page.write_text(f"# {heading}\n")
    assert anchors(page) == {anchor}


def test_repeated_headings_are_numbered_and_code_blocks_are_no_headings(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("## Fleet\n\n```sh\n# Fleet\n```\n\n### Fleet\n\n    text\n\n## Fleet\n")
    assert anchors(page) == {"fleet", "fleet-1", "fleet-2"}
    assert slug("Fleet") == "fleet"


def test_a_missing_file_an_unknown_anchor_and_a_way_out_are_reported(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "other.md").write_text("# Other page\n")
    page = tmp_path / "README.md"
    page.write_text(
        "# Top\n\n"
        "[ok](docs/other.md#other-page), [ok too](#top), [web](https://example.org/x#y)\n"
        "`[in code](missing.md)` and\n\n```sh\n[in a block](missing.md)\n```\n\n"
        "[gone](docs/gone.md) [no anchor](docs/other.md#nothing)\n"
        "[self](#nowhere) [out](../../etc/passwd)\n"
    )
    assert [target for _, target in links(page)] == [
        "docs/other.md#other-page",
        "#top",
        "https://example.org/x#y",
        "docs/gone.md",
        "docs/other.md#nothing",
        "#nowhere",
        "../../etc/passwd",
    ]
    assert broken_links([page], root=tmp_path) == [
        "README.md:10: docs/gone.md: no such file",
        "README.md:10: docs/other.md#nothing: no heading with anchor #nothing",
        "README.md:11: #nowhere: no heading with anchor #nowhere",
        "README.md:11: ../../etc/passwd: outside the repository",
    ]
