"""Warm latency of `joshuac lsp`: diagnostics after a change and completion, against parsing the same text.

    .venv/bin/python bench/lsp.py [--quick]        # --quick: 10 nodes, a few rounds (for the tests)

A real client (pygls) drives `joshuac lsp` over stdio. Each round changes one node's value (a new text, so
nothing is answered from a cache) and times didChange -> publishDiagnostics at the client, then a completion
request in that node. The floor is measured in this process on the same texts: parsing alone
(`syntax_recovery.parse_recovering`) and the whole `check_text` the server runs. Figures are medians in ms.
"""

import argparse
import asyncio
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from compile import description  # noqa: E402

from joshua_codegen.check import check_text  # noqa: E402
from joshua_codegen.syntax_recovery import parse_recovering  # noqa: E402

ROUNDS, QUICK_ROUNDS = 30, 5
WAIT_S = 30.0  # for one answer of the server; only ends a hang


def _texts(nodes: int, rounds: int) -> list[str]:
    base = description(nodes)
    return [base.replace('name: "enc0"', f'name: "enc0_{i}"', 1) for i in range(rounds + 1)]


def _floor(texts: list[str]) -> tuple[float, float]:
    parse, check = [], []
    for text in texts:
        start = time.perf_counter()
        parse_recovering(text)
        parse.append(time.perf_counter() - start)
        start = time.perf_counter()
        check_text("bench.pbtxt", text)
        check.append(time.perf_counter() - start)
    return statistics.median(parse) * 1000, statistics.median(check) * 1000


async def _server(texts: list[str]) -> tuple[float, float]:
    client = LanguageClient("bench", "1")
    published = asyncio.Event()
    client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)(lambda _params: published.set())
    await client.start_io(str(ROOT / ".venv" / "bin" / "joshuac"), "lsp")
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    uri = (ROOT / "bench.pbtxt").as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(uri=uri, language_id="pbtxt", version=0, text=texts[0]))
    )
    await asyncio.wait_for(published.wait(), WAIT_S)
    line = texts[0].split("\n").index(next(x for x in texts[0].split("\n") if "enc0" in x))
    diagnostics, completion = [], []
    for version, text in enumerate(texts[1:], start=1):
        published.clear()
        change = types.TextDocumentContentChangeWholeDocument(text=text)
        start = time.perf_counter()
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(types.VersionedTextDocumentIdentifier(version=version, uri=uri), [change])
        )
        await asyncio.wait_for(published.wait(), WAIT_S)
        diagnostics.append(time.perf_counter() - start)
        params = types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri), position=types.Position(line, 9)
        )
        start = time.perf_counter()
        await asyncio.wait_for(client.text_document_completion_async(params), WAIT_S)
        completion.append(time.perf_counter() - start)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return statistics.median(diagnostics) * 1000, statistics.median(completion) * 1000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    quick = parser.parse_args().quick
    nodes, rounds = (10, QUICK_ROUNDS) if quick else (100, ROUNDS)
    texts = _texts(nodes, rounds)
    parse_ms, check_ms = _floor(texts)
    diagnostics_ms, completion_ms = asyncio.run(_server(texts))
    print(f"{nodes} nodes, median of {rounds} changes")
    print(f"floor: parse {parse_ms:.2f} ms, check_text {check_ms:.2f} ms (in this process)")
    print(f"lsp: change -> diagnostics {diagnostics_ms:.2f} ms ({diagnostics_ms / parse_ms:.1f}x parse)")
    print(f"lsp: completion {completion_ms:.2f} ms ({completion_ms / parse_ms:.1f}x parse)")


if __name__ == "__main__":
    main()
