"""The picture of the runtime's layers in docs/architecture.md shows the import-linter contract of pyproject.toml."""

import re
import tomllib

from testsupport.documents import ROOT

ARCHITECTURE = ROOT / "docs" / "architecture.md"
RUNTIME_CONTAINER = "joshua_runtime"
# The subgraph of the layers picture that draws the runtime's layers, one box a layer, top to bottom.
SUBGRAPH = re.compile(r"^\s*subgraph inside\b.*?\n(.*?)^\s*end$", re.MULTILINE | re.DOTALL)
BOX = re.compile(r'^\s*\w+\["([^"]*)"\]\s*$', re.MULTILINE)


def contract_layers() -> list[set[str]]:
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    (runtime,) = [c for c in contracts if c.get("containers") == [RUNTIME_CONTAINER]]
    return [{name.strip() for name in re.split(r"[|:]", layer)} for layer in runtime["layers"]]


def picture_layers(text: str) -> list[set[str]]:
    subgraph = SUBGRAPH.search(text)
    assert subgraph, "docs/architecture.md has no `subgraph inside` of the runtime's layers"
    labels = BOX.findall(subgraph.group(1))
    return [{name.strip() for name in label.replace("<br/>", " ").split(",")} for label in labels]


def test_the_runtime_layers_picture_is_the_contract():
    assert picture_layers(ARCHITECTURE.read_text()) == contract_layers()


def test_a_layer_left_out_of_the_picture_is_noticed():
    text = ARCHITECTURE.read_text().replace(', presets, graph"]', ', presets"]')
    assert picture_layers(text) != contract_layers()
