"""``ncverify lsp`` end to end over stdio, with pytest-lsp playing VS Code and Neovim."""
from __future__ import annotations

import asyncio
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

if not os.environ.get("CI"):  # in CI the test extra installs it: a missing pygls fails there
    pytest.importorskip("pygls", reason="the lsp extra is not installed")
import pytest_lsp  # noqa: E402
from lsprotocol import types  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities  # noqa: E402

from ncverify import Settings, check_text  # noqa: E402
from ncverify.rule_pages import explain_text  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT / "corpus"
SERVER = [sys.executable, "-m", "ncverify.cli", "lsp"]
BRACKET = CORPUS / "iso" / "quickstart-bracket.nc"


# One server per client kind for the whole module: each test opens its own documents.
@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER), params=["visual-studio-code", "neovim"], scope="module")
async def client(request, lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=client_capabilities(request.param), root_uri=ROOT.as_uri(),
        initialization_options={"ncverify": {"debounceMs": 10}}))
    yield
    await lsp_client.shutdown_session()


def _pull_capabilities() -> types.ClientCapabilities:
    return types.ClientCapabilities(text_document=types.TextDocumentClientCapabilities(
        diagnostic=types.DiagnosticClientCapabilities(related_document_support=True)))


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER), scope="module")
async def pull_client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(types.InitializeParams(
        capabilities=_pull_capabilities(), initialization_options={"disabledRules": ["core.tool-not-in-table"]}))
    yield
    await lsp_client.shutdown_session()


async def open_and_wait(client: LanguageClient, path: Path, text: str | None = None) -> list[types.Diagnostic]:
    uri = path.resolve().as_uri()
    client.diagnostics.pop(uri, None)
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id="gcode", version=1, text=path.read_text(encoding="utf-8") if text is None else text)))
    return await wait_diagnostics(client, uri)


async def wait_diagnostics(client: LanguageClient, uri: str, timeout: float = 60) -> list[types.Diagnostic]:
    """Pulled from a client that pulls (Neovim 0.10+, the server pushes nothing to it), else
    the next push."""
    if client.capabilities.text_document.diagnostic is not None:
        report = await asyncio.wait_for(client.text_document_diagnostic_async(types.DocumentDiagnosticParams(
            text_document=types.TextDocumentIdentifier(uri=uri))), timeout)
        return list(report.items)

    async def arrived():
        while uri not in client.diagnostics:
            await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        return client.diagnostics[uri]
    return list(await asyncio.wait_for(arrived(), timeout))


def _findings(diagnostics) -> set[tuple[int, str]]:
    return {(item.range.start.line + 1, item.code) for item in diagnostics}


@pytest.mark.asyncio(loop_scope="module")
async def test_diagnostics_are_the_findings_of_check_with_rule_pages_and_no_unknown_as_error(client: LanguageClient):
    diagnostics = await open_and_wait(client, BRACKET)
    expected = check_file_findings(BRACKET)
    assert _findings(diagnostics) == {(d.span.line, d.rule) for d in expected}
    by_rule = {item.code: item for item in diagnostics}
    assert by_rule["core.comp-on-arc"].severity == types.DiagnosticSeverity.Error
    assert by_rule["core.comp-on-arc"].code_description.href.endswith("rules/core/comp-on-arc.md")
    unknown = [item for item in diagnostics if item.message.startswith("unknown:")]
    assert unknown and all(item.severity in (types.DiagnosticSeverity.Information, types.DiagnosticSeverity.Hint) for item in unknown)
    tool_finding = by_rule["core.length-offset-mismatch"]
    assert any(info.location.range.start.line == 21 for info in tool_finding.related_information)  # T2 M06


def check_file_findings(path: Path):
    from ncverify import check_file

    return check_file(path).diagnostics


@pytest.mark.asyncio(loop_scope="module")
async def test_an_edit_is_checked_again_and_a_fixed_line_loses_its_finding(client: LanguageClient):
    text = BRACKET.read_text(encoding="utf-8")
    await open_and_wait(client, BRACKET)
    uri = BRACKET.resolve().as_uri()
    client.diagnostics.pop(uri, None)
    fixed = text.replace("G41 D01 G02 X0. Y0. R10.", "G41 D01 G01 X0. Y0.")
    line = text.splitlines().index("G41 D01 G02 X0. Y0. R10.")
    client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text=fixed)]))
    diagnostics = await wait_diagnostics(client, uri)
    assert (line + 1, "core.comp-on-arc") not in _findings(diagnostics)
    assert (23, "core.length-offset-mismatch") in _findings(diagnostics)


@pytest.mark.asyncio(loop_scope="module")
@pytest.mark.parametrize("path", [CORPUS / "heidenhain" / "pocket.h", CORPUS / "sinumerik" / "shifted-arguments.mpf",
                                  CORPUS / "fagor" / "bad-cycle-left-active.pim"], ids=lambda p: p.parent.name)
async def test_every_dialect_is_served(client: LanguageClient, path: Path):
    diagnostics = await open_and_wait(client, path)
    assert _findings(diagnostics) == {(d.span.line, d.rule) for d in check_file_findings(path) if not d.span.path}


@pytest.mark.asyncio(loop_scope="module")
async def test_pull_diagnostics_with_settings_from_initialization_options(pull_client: LanguageClient):
    uri = BRACKET.resolve().as_uri()
    pull_client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id="gcode", version=1, text=BRACKET.read_text(encoding="utf-8"))))
    report = await pull_client.text_document_diagnostic_async(types.DocumentDiagnosticParams(
        text_document=types.TextDocumentIdentifier(uri=uri)))
    rules = {item.code for item in report.items}
    assert "core.comp-on-arc" in rules and "core.tool-not-in-table" not in rules
    assert uri not in pull_client.diagnostics  # nothing pushed to a client that pulls


async def _hover(client, path: Path, line: int, character: int) -> str:
    answer = await client.text_document_hover_async(types.HoverParams(
        text_document=types.TextDocumentIdentifier(uri=path.resolve().as_uri()), position=types.Position(line=line, character=character)))
    return answer.contents.value if answer else ""


def _position(path: Path, needle: str, offset: int = 0) -> tuple[int, int]:
    for number, text in enumerate(path.read_text(encoding="utf-8").splitlines()):
        if needle in text:
            return number, text.index(needle) + offset
    raise AssertionError(f"{needle!r} not in {path}")


@pytest.mark.asyncio(loop_scope="module")
async def test_hover_explains_codes_cycle_parameters_and_findings(client: LanguageClient, tmp_path: Path):
    await open_and_wait(client, BRACKET)
    assert "peck" in await _hover(client, BRACKET, *_position(BRACKET, "G83"))
    line, column = _position(BRACKET, "G41 D01 G02")
    page = await _hover(client, BRACKET, line, column + 9)
    assert explain_text("core.comp-on-arc") in page and "circular interpolation CW" in page
    assert "R point" in await _hover(client, BRACKET, *_position(BRACKET, "R2.", 0))
    parametric = CORPUS / "iso" / "param-depth-violated.nc"
    await open_and_wait(client, parametric)
    line = next(number for number, text in enumerate(parametric.read_text(encoding="utf-8").splitlines()) if "Z#1" in text.replace(" ", "") or "Z[#1" in text)
    column = parametric.read_text(encoding="utf-8").splitlines()[line].index("#1")
    assert "free parameter" in await _hover(client, parametric, line, column)

    sinumerik = tmp_path / "part.mpf"
    sinumerik.write_text("G17 G90 T1 D1 M6\nS1000 M3\nG0 X0 Y0 Z50\nCYCLE81(50, 0, 2, -10)\nM30\n", encoding="utf-8")
    await open_and_wait(client, sinumerik)
    assert "**SDIS**" in await _hover(client, sinumerik, 3, 15)  # the third argument
    heidenhain = CORPUS / "heidenhain" / "drilling-clean.h"
    await open_and_wait(client, heidenhain)
    assert "depth" in await _hover(client, heidenhain, *_position(heidenhain, "Q201="))
    fagor = CORPUS / "fagor" / "bad-cycle-left-active.pim"
    await open_and_wait(client, fagor)
    assert "drilling depth" in await _hover(client, fagor, *_position(fagor, "I-15"))


@pytest.mark.asyncio(loop_scope="module")
async def test_inlay_hints_name_positional_cycle_arguments(client: LanguageClient, tmp_path: Path):
    program = tmp_path / "hints.mpf"
    program.write_text("T1 D1 M6\nS1000 M3\nCYCLE81(50, 0, , -10)\nM30\n", encoding="utf-8")
    await open_and_wait(client, program)
    hints = await client.text_document_inlay_hint_async(types.InlayHintParams(
        text_document=types.TextDocumentIdentifier(uri=program.as_uri()),
        range=types.Range(start=types.Position(line=0, character=0), end=types.Position(line=3, character=0))))
    assert [(hint.label, hint.position.character) for hint in hints] == [("RTP:", 8), ("RFP:", 12), ("DP:", 17)]


@pytest.mark.asyncio(loop_scope="module")
async def test_values_the_interpreter_computed_in_inlay_hints_and_hover(client: LanguageClient, tmp_path: Path):
    program = tmp_path / "macro.nc"
    program.write_text("O1000\n#1=0\nWHILE [#1 LT 3] DO1\n#1=#1+1\nEND1\n#2=#500*2\nG00 X#2\nM30\n", encoding="utf-8")
    await open_and_wait(client, program)
    hints = await client.text_document_inlay_hint_async(types.InlayHintParams(
        text_document=types.TextDocumentIdentifier(uri=program.as_uri()),
        range=types.Range(start=types.Position(line=0, character=0), end=types.Position(line=7, character=0))))
    assert {(hint.position.line, hint.label) for hint in hints} == {(1, "#1 = 0"), (3, "#1 = 1, 2, 3"), (5, "#2 = 2*#500")}
    assert "**#2** = 2*#500 (assigned at line 6)" in await _hover(client, program, 6, 6)
    assert "free parameter" in await _hover(client, program, 5, 5)


async def _actions(client, path: Path, diagnostic: types.Diagnostic) -> list[types.CodeAction]:
    return await client.text_document_code_action_async(types.CodeActionParams(
        text_document=types.TextDocumentIdentifier(uri=path.resolve().as_uri()), range=diagnostic.range,
        context=types.CodeActionContext(diagnostics=[diagnostic])))


def _apply(text: str, edit: types.TextEdit) -> str:
    lines = text.splitlines(keepends=True)
    start = sum(len(line) for line in lines[:edit.range.start.line]) + edit.range.start.character
    end = sum(len(line) for line in lines[:edit.range.end.line]) + edit.range.end.character
    return text[:start] + edit.new_text + text[end:]


@pytest.mark.asyncio(loop_scope="module")
async def test_code_actions_suppress_and_fix_and_the_check_agrees(client: LanguageClient, tmp_path: Path):
    program = tmp_path / "modal.nc"
    program.write_text("O1000\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS1000 M03\nG99 G81 X10. Y10. Z-5. R2. F100.\n"
                       "X20.\nT2 M06\nG01 X0. Y0.\nM30\n", encoding="utf-8")
    text = program.read_text(encoding="utf-8")
    diagnostics = await open_and_wait(client, program)
    modal = next(item for item in diagnostics if item.code == "core.cycle-modal-at-tool-change")
    actions = {action.title: action for action in await _actions(client, program, modal)}
    insert = next(action for title, action in actions.items() if title.startswith("Insert G80"))
    fixed = _apply(text, insert.edit.changes[program.as_uri()][0])
    assert "core.cycle-modal-at-tool-change" not in {d.rule for d in check_text(fixed).diagnostics}
    suppress = next(action for title, action in actions.items() if title.startswith("Suppress"))
    quiet = _apply(text, suppress.edit.changes[program.as_uri()][0])
    result = check_text(quiet)
    assert "core.cycle-modal-at-tool-change" not in {d.rule for d in result.diagnostics}
    assert "core.cycle-modal-at-tool-change" in {item.rule for item in result.suppressed}


@pytest.mark.asyncio(loop_scope="module")
async def test_the_feed_fix_moves_the_first_feed_up_to_the_move_that_has_none(client: LanguageClient, tmp_path: Path):
    program = tmp_path / "feed.nc"
    program.write_text("O1000\nG21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS1000 M03\nG00 X0. Y0.\nG01 Z-1.\nX20. F250.\nG00 Z50.\nM30\n",
                       encoding="utf-8")
    diagnostics = await open_and_wait(client, program)
    missing = next(item for item in diagnostics if item.code == "core.feed-missing")
    action = next(action for action in await _actions(client, program, missing) if action.title.startswith("Add the feed"))
    assert action.title == "Add the feed F250. programmed next"
    fixed = _apply(program.read_text(encoding="utf-8"), action.edit.changes[program.as_uri()][0])
    assert fixed.splitlines()[6] == "G01 Z-1. F250."
    assert "core.feed-missing" not in {d.rule for d in check_text(fixed).diagnostics}


@pytest.mark.asyncio(loop_scope="module")
async def test_navigation_symbols_definitions_references_and_folds(client: LanguageClient, tmp_path: Path):
    main = tmp_path / "main.nc"
    main.write_text("O1000\nG21 G90 G54\n#1=0\nWHILE [#1 LT 3] DO1\n#1=#1+1\nEND1\nGOTO 20\nN10 G00 X0.\nN20 M98 P2000\nM30\n",
                    encoding="utf-8")
    (tmp_path / "O2000.nc").write_text("O2000\nG00 X5.\nM99\n", encoding="utf-8")
    await open_and_wait(client, main)
    document = types.TextDocumentIdentifier(uri=main.as_uri())
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=document))
    assert {"O1000", "N10", "N20"} <= {symbol.name for symbol in symbols}
    target = await client.text_document_definition_async(types.DefinitionParams(text_document=document, position=types.Position(line=6, character=5)))
    assert [location.range.start.line for location in target] == [8]
    other = await client.text_document_definition_async(types.DefinitionParams(text_document=document, position=types.Position(line=8, character=10)))
    assert [location.uri for location in other] == [(tmp_path / "O2000.nc").as_uri()]
    found = await client.text_document_references_async(types.ReferenceParams(
        text_document=document, position=types.Position(line=8, character=1), context=types.ReferenceContext(include_declaration=False)))
    assert [location.range.start.line for location in found] == [6]
    folds = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=document))
    assert (3, 5) in {(fold.start_line, fold.end_line) for fold in folds}


@pytest.mark.asyncio(loop_scope="module")
async def test_heidenhain_labels_and_called_programs(client: LanguageClient):
    path = CORPUS / "heidenhain" / "label-subprogram.h"
    await open_and_wait(client, path)
    document = types.TextDocumentIdentifier(uri=path.resolve().as_uri())
    line, column = _position(path, "CALL LBL", 9)
    target = await client.text_document_definition_async(types.DefinitionParams(text_document=document, position=types.Position(line=line, character=column)))
    assert target and "LBL" in path.read_text(encoding="utf-8").splitlines()[target[0].range.start.line]
    folds = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=document))
    assert folds


@pytest.mark.asyncio(loop_scope="module")
async def test_binary_junk_and_a_document_closed_during_analysis_leave_the_server_working(client: LanguageClient, tmp_path: Path):
    junk = tmp_path / "junk.nc"
    junk.write_bytes(bytes(range(256)) * 40)
    diagnostics = await open_and_wait(client, junk, text=junk.read_bytes().decode("latin-1"))
    assert all(item.severity != types.DiagnosticSeverity.Error for item in diagnostics)
    big = tmp_path / "big.nc"
    big.write_text("O1000\nG21 G90 G54\nS1000 M03\n" + "G01 X1. Y1. F100.\nX2. Y2.\n" * 20000 + "M30\n", encoding="utf-8")
    uri = big.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
        uri=uri, language_id="gcode", version=1, text=big.read_text(encoding="utf-8"))))
    client.text_document_did_close(types.DidCloseTextDocumentParams(text_document=types.TextDocumentIdentifier(uri=uri)))
    assert await open_and_wait(client, BRACKET)


def _message(payload: dict) -> bytes:
    body = json.dumps(payload).encode("utf-8")
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def test_a_malformed_request_gets_an_error_and_the_server_exits_when_its_client_disappears():
    process = subprocess.Popen(SERVER, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    process.stdin.write(_message({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}))
    process.stdin.write(_message({"jsonrpc": "2.0", "id": 2, "method": "textDocument/hover", "params": {"textDocument": 5}}))
    process.stdin.write(b"Content-Length: 7\r\n\r\n{junk!}")
    process.stdin.write(_message({"jsonrpc": "2.0", "id": 3, "method": "shutdown"}))
    process.stdin.close()  # the client disappears without sending exit
    output = process.stdout.read()
    assert process.wait(timeout=60) == 0
    answers = [json.loads(part.split(b"\r\n\r\n", 1)[1]) for part in output.split(b"Content-Length")[1:]]
    by_id = {answer.get("id"): answer for answer in answers}
    assert "capabilities" in by_id[1]["result"] and "result" in by_id[3]  # still answering after the junk
    assert any(answer.get("method") == "window/showMessage" and "Invalid Params" in answer["params"]["message"] for answer in answers)


def test_settings_of_the_editor_win_over_the_project_file_and_bad_values_are_ignored(tmp_path: Path):
    from ncverify.lsp.analysis import EditorSettings, analyse

    (tmp_path / "ncverify.toml").write_text('[settings]\nmachine = "lathe"\n[rules]\ndisable = ["core.comp-on-arc"]\n', encoding="utf-8")
    program = tmp_path / "part.nc"
    text = BRACKET.read_text(encoding="utf-8")
    editor = EditorSettings.from_json({"machine": "mill", "solverTimeout": "soon", "disabledRules": ["core.tool-not-in-table", 3]})
    result, problem, _ = analyse(text, program, str(program), editor.settings())
    assert problem is None and result.machine == "mill"
    rules = {d.rule for d in result.diagnostics}
    assert "core.comp-on-arc" not in rules and "core.tool-not-in-table" not in rules
    assert editor.settings().solver_timeout_s == Settings().solver_timeout_s


def test_a_newer_version_ends_the_worker_checking_the_older_one():
    from ncverify.lsp.analysis import EditorSettings, Runner

    # a comment on each line keeps it off the array reader: seconds of checking, not a fifth
    # of one, so the older version is still being checked when the newer one comes
    big = "O1000\nG21 G90 G54\nS1000 M03\n" + "G01 X1. Y1. F100. (A)\nX2. Y2. (B)\n" * 100000 + "M30\n"
    small = BRACKET.read_text(encoding="utf-8")
    settings = EditorSettings().settings()

    async def race():
        runner = Runner()
        try:
            slow = asyncio.ensure_future(runner.run("doc", big, None, "doc", settings))
            await asyncio.sleep(0.5)
            worker = runner._busy["doc"]
            fast = await runner.run("doc", small, None, "doc", settings)
            return await slow, worker.process.is_alive(), fast
        finally:
            runner.cancel_all()

    stale, alive, fresh = asyncio.run(race())
    assert stale is None and not alive
    assert "core.comp-on-arc" in {d.rule for d in fresh[0].diagnostics}
