"""Time ``ncverify lsp`` as an editor sees it: from the client's didChange to the
diagnostics of that version, for a 5,000-line program, and the hover latency while a
200,000-line program is being checked.

    python benchmarks/lsp.py [--lines 5000] [--edits 10]
"""
from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient


def program(lines: int) -> str:
    body = [f"G01 X{i % 100}.{i % 10} Y{(i * 7) % 80}. F800." if i % 2 else f"X{(i * 3) % 100}. Y{i % 80}." for i in range(lines - 8)]
    return "\n".join(["%", "O1000", "(ncverify: stock box X0:120 Y0:80 Z-25:0)", "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50. S6000 M03",
                      "G00 X0. Y0. Z2.", *body, "M30"]) + "\n"


async def measure(lines: int, edits: int) -> None:
    published: dict[int, float] = {}
    client = LanguageClient("ncverify-benchmark", "1")

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def diagnostics(params: types.PublishDiagnosticsParams):
        published.setdefault(params.version, time.perf_counter())

    await client.start_io(sys.executable, "-m", "ncverify.cli", "lsp")
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities(), initialization_options={"debounceMs": 0}))
    client.initialized(types.InitializedParams())
    folder = Path(tempfile.mkdtemp())
    uri = (folder / "bench.nc").as_uri()
    text = program(lines)
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(uri=uri, language_id="gcode", version=1, text=text)))
    await _until(lambda: 1 in published)
    delays = []
    for version in range(2, edits + 2):
        text = text.replace("G00 X0. Y0. Z2.", f"G00 X0. Y0. Z{version}.")
        start = time.perf_counter()
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))
        await _until(lambda: version in published)
        delays.append((published[version] - start) * 1000)
    print(f"{lines:,} lines: didChange to diagnostics median {statistics.median(delays):.0f} ms, max {max(delays):.0f} ms ({edits} edits)")

    big = (folder / "big.nc").as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(uri=big, language_id="gcode", version=1, text=program(200_000))))
    hovers = []
    for _ in range(10):
        start = time.perf_counter()
        await client.text_document_hover_async(types.HoverParams(text_document=types.TextDocumentIdentifier(uri=big), position=types.Position(line=3, character=1)))
        hovers.append((time.perf_counter() - start) * 1000)
    print(f"200,000 lines being checked: first hover {hovers[0]:.0f} ms (the server reads the 4 MB didOpen first), "
          f"then median {statistics.median(hovers[1:]):.0f} ms, max {max(hovers[1:]):.0f} ms")
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()


async def _until(condition, timeout: float = 120) -> None:
    end = time.perf_counter() + timeout
    while not condition():
        if time.perf_counter() > end:
            raise TimeoutError("no diagnostics")
        await asyncio.sleep(0.002)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--lines", type=int, default=5000)
    parser.add_argument("--edits", type=int, default=10)
    options = parser.parse_args()
    asyncio.run(measure(options.lines, options.edits))
