"""The language server: ``ncverify check`` for the buffer being edited, plus what the
dialect tables and the program's outline can tell about the text under the cursor."""
from __future__ import annotations

import asyncio
import logging
import re
from dataclasses import dataclass, field
from pathlib import Path

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import to_fs_path

from .. import __version__
from ..api import FileResult
from ..rule_pages import explain_text
from ..detect import detect
from .actions import code_actions
from .analysis import EditorSettings, Runner
from .convert import SOURCE, LineIndex, to_diagnostics
from .knowledge import cycle_calls, hover_markdown, parameter_names
from .navigation import Outline, outline

logger = logging.getLogger(__name__)
SECTION = "ncverify"


@dataclass
class Analysis:
    """The last finished check of one document version."""

    version: int | None
    result: FileResult | None
    diagnostics: list[types.Diagnostic] = field(default_factory=list)


class NcVerifyServer(LanguageServer):
    def __init__(self):
        super().__init__("ncverify", __version__, text_document_sync_kind=types.TextDocumentSyncKind.Incremental)
        self.runner = Runner()
        self.editor = EditorSettings()
        self.root: Path | None = None
        self.analyses: dict[str, Analysis] = {}
        self.pending: dict[str, asyncio.Task] = {}
        self.pull = False
        self.outlines: dict[str, tuple[int | None, Outline]] = {}
        self.detections: dict[str, object] = {}  # uri -> the Detection settled at open or save
        self.split: dict[str, tuple[int | None, list[str]]] = {}
        self.guesses: dict[str, object] = {}  # uri -> a Detection made for hover before any analysis

    # ------------------------------------------------------------------ analysis

    def schedule(self, uri: str, delay: float | None = None, detect_again: bool = False) -> None:
        """Check the document's current version after the debounce delay; an older check
        of the same document, waiting or running, is abandoned. The dialect is detected
        again on open, save and settings changes, and kept while the user types."""
        self.forget_pending(uri)
        if detect_again:
            self.detections.pop(uri, None)
        document = self.workspace.get_text_document(uri)
        wait = self.editor.debounce_ms / 1000 if delay is None else delay
        task = asyncio.get_running_loop().create_task(self._analyse(uri, document.version, wait))
        task.add_done_callback(_log_failure)
        self.pending[uri] = task

    def forget_pending(self, uri: str) -> None:
        task = self.pending.pop(uri, None)
        if task is not None:
            task.cancel()
        self.runner.cancel(uri)

    async def _analyse(self, uri: str, version: int | None, wait: float) -> None:
        if wait:
            await asyncio.sleep(wait)
        document = self.workspace.get_text_document(uri)
        text = document.source
        path = Path(to_fs_path(uri)) if uri.startswith("file:") else None
        answer = await self.runner.run(uri, text, path, str(path or uri), self.check_settings(), self.detections.get(uri))
        if uri not in self.workspace.text_documents or self.workspace.get_text_document(uri).version != version:
            return  # superseded, or the document was closed meanwhile
        # No answer for the current version: the worker ended on its own (a newer version
        # would have cancelled this task before it got here).
        result, problem, detection = answer or (None, "ncverify: the analysis stopped unexpectedly (its worker process ended)", None)
        if detection is not None and detection.dialect is not None:
            self.detections[uri] = detection
        analysis = Analysis(version, result)
        if problem:
            analysis.diagnostics = [_file_level(problem, types.DiagnosticSeverity.Error)]
        elif result.skipped:
            analysis.diagnostics = [_file_level(f"not checked: {result.skipped}", types.DiagnosticSeverity.Information)]
        else:
            analysis.diagnostics = to_diagnostics(result, uri, LineIndex(text, result.dialect))
        self.analyses[uri] = analysis
        if not self.pull:
            self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=analysis.diagnostics, version=version))

    async def current(self, uri: str) -> Analysis | None:
        """The analysis of the document's current version, waiting for it if it is due."""
        while True:
            task = self.pending.get(uri)
            if task is None or task.done():
                break
            try:
                await asyncio.shield(task)
            except asyncio.CancelledError:
                if asyncio.current_task().cancelling():
                    raise
        analysis = self.analyses.get(uri)
        if uri in self.workspace.text_documents and (analysis is None or analysis.version != self.workspace.get_text_document(uri).version):
            self.schedule(uri, delay=0)
            return await self.current(uri)
        return analysis

    def check_settings(self):
        settings = self.editor.settings()
        if settings.config is not None and not settings.config.is_absolute() and self.root is not None:
            settings = settings.with_(config=self.root / settings.config)
        return settings

    def last(self, uri: str) -> Analysis | None:
        """The latest finished analysis, whatever its version: hover never waits for one."""
        return self.analyses.get(uri)

    def dialect_of(self, uri: str) -> tuple[str | None, str | None, str | None]:
        analysis = self.last(uri)
        if analysis is not None and analysis.result is not None and analysis.result.dialect:
            return analysis.result.dialect, analysis.result.profile, analysis.result.machine
        found = self.detections.get(uri) or self.guesses.get(uri)
        if found is None:  # before the first analysis: detected once here, then settled by the analysis
            head = self.workspace.get_text_document(uri).source[:65536]
            found = self.guesses[uri] = detect(head, head.encode("utf-8", errors="replace"))
        return self.editor.dialect or found.dialect, self.editor.profile or found.profile, self.editor.machine or found.machine

    def lines_of(self, uri: str) -> list[str]:
        """The document's lines without their ends, split once per version (a 200,000-line
        buffer is not split again for every hover)."""
        document = self.workspace.get_text_document(uri)
        cached = self.split.get(uri)
        if cached is None or cached[0] != document.version:
            cached = self.split[uri] = (document.version, document.source.splitlines())
        return cached[1]

    def outline_of(self, uri: str) -> Outline:
        document = self.workspace.get_text_document(uri)
        cached = self.outlines.get(uri)
        if cached is None or cached[0] != document.version:
            cached = (document.version, outline(self.lines_of(uri), self.dialect_of(uri)[0]))
            self.outlines[uri] = cached
        return cached[1]

    async def load_configuration(self) -> None:
        capabilities = self.client_capabilities.workspace
        if capabilities is None or not capabilities.configuration:
            return
        try:
            answer = await self.workspace_configuration_async(types.ConfigurationParams(items=[types.ConfigurationItem(section=SECTION)]))
        except Exception as error:  # noqa: BLE001 - a client that cannot answer keeps the initial settings
            logger.warning("workspace/configuration failed: %s", error)
            return
        if answer and isinstance(answer[0], dict):
            self.editor = EditorSettings.from_json(answer[0])

    def reanalyse_all(self) -> None:
        for uri in list(self.workspace.text_documents):
            self.schedule(uri, delay=0, detect_again=True)
        diagnostics = self.client_capabilities.workspace.diagnostics if self.client_capabilities.workspace else None
        if self.pull and diagnostics is not None and diagnostics.refresh_support:
            self.workspace_diagnostic_refresh(None)


def _log_failure(task: asyncio.Task) -> None:
    if not task.cancelled() and task.exception() is not None:
        logger.error("analysis failed", exc_info=task.exception())


def _file_level(message: str, severity: types.DiagnosticSeverity) -> types.Diagnostic:
    start = types.Position(line=0, character=0)
    return types.Diagnostic(range=types.Range(start=start, end=start), message=message, severity=severity, source=SOURCE)


server = NcVerifyServer()


@server.feature(types.INITIALIZE)
def initialize(ls: NcVerifyServer, params: types.InitializeParams) -> None:
    ls.runner.warm_up()
    ls.editor = EditorSettings.from_json(params.initialization_options)
    text_document = params.capabilities.text_document
    ls.pull = bool(text_document and text_document.diagnostic)
    root = params.root_uri or (params.workspace_folders[0].uri if params.workspace_folders else None)
    ls.root = Path(to_fs_path(root)) if root and root.startswith("file:") else None


@server.feature(types.INITIALIZED)
async def initialized(ls: NcVerifyServer, params: types.InitializedParams) -> None:
    await ls.load_configuration()


@server.feature(types.WORKSPACE_DID_CHANGE_CONFIGURATION)
async def configuration_changed(ls: NcVerifyServer, params: types.DidChangeConfigurationParams) -> None:
    if isinstance(params.settings, dict) and params.settings:
        ls.editor = EditorSettings.from_json(params.settings)
    else:
        await ls.load_configuration()
    ls.reanalyse_all()


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: NcVerifyServer, params: types.DidOpenTextDocumentParams) -> None:
    ls.schedule(params.text_document.uri, delay=0, detect_again=True)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: NcVerifyServer, params: types.DidChangeTextDocumentParams) -> None:
    ls.schedule(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: NcVerifyServer, params: types.DidSaveTextDocumentParams) -> None:
    ls.schedule(params.text_document.uri, delay=0, detect_again=True)


@server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: NcVerifyServer, params: types.DidCloseTextDocumentParams) -> None:
    uri = params.text_document.uri
    ls.forget_pending(uri)
    ls.analyses.pop(uri, None)
    ls.outlines.pop(uri, None)
    ls.detections.pop(uri, None)
    ls.guesses.pop(uri, None)
    ls.split.pop(uri, None)
    if not ls.pull:
        ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


@server.feature(types.TEXT_DOCUMENT_DIAGNOSTIC, types.DiagnosticOptions(identifier=SECTION, inter_file_dependencies=True, workspace_diagnostics=False))
async def pull_diagnostics(ls: NcVerifyServer, params: types.DocumentDiagnosticParams) -> types.DocumentDiagnosticReport:
    analysis = await ls.current(params.text_document.uri)
    items = analysis.diagnostics if analysis else []
    return types.RelatedFullDocumentDiagnosticReport(items=items, result_id=str(analysis.version) if analysis else None)


@server.feature(types.TEXT_DOCUMENT_HOVER)
def hover(ls: NcVerifyServer, params: types.HoverParams) -> types.Hover | None:
    uri, position = params.text_document.uri, params.position
    parts = []
    analysis = ls.last(uri)
    if analysis is not None:
        for diagnostic in analysis.diagnostics:
            if _contains(diagnostic.range, position) and diagnostic.code:
                page = explain_text(str(diagnostic.code))
                if page and page not in parts:
                    parts.append(page)
    dialect, profile, machine = ls.dialect_of(uri)
    described = hover_markdown(dialect, profile, machine, ls.lines_of(uri), position.line, position.character)
    if described:
        parts.insert(0, described)
    if analysis is not None and analysis.result is not None and (variable := _variable_at(ls.lines_of(uri), position, analysis.result)):
        parts.insert(0, variable)
    if not parts:
        return None
    return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value="\n\n---\n\n".join(parts)))


_VARIABLE = re.compile(r"(?i)#\d+|\bQ[LR]?\d+|\bR\d+|\bP\d+|\b[A-Z_][A-Z0-9_]*")
_SHOWN_VALUES = 4


def _variable_at(lines: list[str], position: types.Position, result: FileResult) -> str | None:
    """What the analysis knows of the variable under the cursor: free (read, never set), or
    the values its last assignment above this line computed."""
    if not 0 <= position.line < len(lines):
        return None
    for match in _VARIABLE.finditer(lines[position.line]):
        if not match.start() <= position.character <= match.end():
            continue
        name = match.group().upper()
        if name in result.free_parameters:
            return (f"**{name}**: a free parameter: the program reads it and never sets it, so every check "
                    "holds it as any value the `assume` annotations and `[assume]` of the project file allow")
        assigned = [(line, value) for line, pairs in result.values.items() if line <= position.line + 1
                    for variable, value in pairs if variable.upper() == name]
        if assigned:
            line = max(line for line, _ in assigned)
            return f"**{name}** = " + _values_text([value for at, value in assigned if at == line]) + f" (assigned at line {line})"
    return None


def _values_text(shown: list[str]) -> str:
    """The distinct values one line computed (a loop runs it several times), in order."""
    distinct = list(dict.fromkeys(shown))
    text = ", ".join(distinct[:_SHOWN_VALUES])
    return text + (", ..." if len(distinct) > _SHOWN_VALUES else "")


def _contains(region: types.Range, position: types.Position) -> bool:
    start, end = (region.start.line, region.start.character), (region.end.line, region.end.character)
    here = (position.line, position.character)
    return start <= here <= end or (region.start.line == position.line and start == end)


@server.feature(types.TEXT_DOCUMENT_INLAY_HINT)
def inlay_hints(ls: NcVerifyServer, params: types.InlayHintParams) -> list[types.InlayHint]:
    uri = params.text_document.uri
    lines = ls.lines_of(uri)
    hints = []
    first, last = max(params.range.start.line, 0), min(params.range.end.line, len(lines) - 1)
    analysis = ls.last(uri)
    if analysis is not None and analysis.result is not None and analysis.version == ls.workspace.get_text_document(uri).version:
        for line, assigned in sorted(analysis.result.values.items()):
            if first <= line - 1 <= last < len(lines):
                # only what the line itself writes (a D word sets $P_TOOL behind the scenes)
                written = [(name, value) for name, value in assigned if name.upper() in lines[line - 1].upper()]
                if written:
                    hints.append(_value_hint(lines[line - 1], line - 1, written))
    if ls.dialect_of(uri)[0] != "sinumerik":
        return hints
    for number in range(first, last + 1):
        for call in cycle_calls(lines[number]):
            names = parameter_names(call.name)
            for argument in call.arguments:
                if argument.text and argument.index < len(names):
                    hints.append(types.InlayHint(
                        position=types.Position(line=number, character=argument.start), label=f"{names[argument.index][0]}:",
                        kind=types.InlayHintKind.Parameter, padding_right=True))
    return hints


def _value_hint(text: str, line: int, assigned: list[tuple[str, str]]) -> types.InlayHint:
    """``= value`` after an assignment the interpreter evaluated."""
    by_name: dict[str, list[str]] = {}
    for name, value in assigned:
        by_name.setdefault(name, []).append(value)
    label = "; ".join(f"{name} = {_values_text(shown)}" for name, shown in by_name.items())
    return types.InlayHint(position=types.Position(line=line, character=len(text)), label=label, padding_left=True)


@server.feature(types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]))
def actions(ls: NcVerifyServer, params: types.CodeActionParams) -> list[types.CodeAction]:
    uri = params.text_document.uri
    return code_actions(uri, ls.lines_of(uri), ls.dialect_of(uri)[0], params.context.diagnostics)


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def document_symbols(ls: NcVerifyServer, params: types.DocumentSymbolParams) -> list[types.DocumentSymbol]:
    lines = ls.lines_of(params.text_document.uri)
    symbols = []
    for symbol in ls.outline_of(params.text_document.uri).symbols:
        last = min(max(symbol.last_line, symbol.place.line), len(lines) - 1)
        whole = types.Range(start=types.Position(line=symbol.place.line, character=0),
                            end=types.Position(line=last, character=len(lines[last]) if lines else 0))
        selection = symbol.place.range()
        if selection.end.line == whole.end.line and selection.end.character > whole.end.character:
            whole = types.Range(start=whole.start, end=selection.end)
        symbols.append(types.DocumentSymbol(name=symbol.name, kind=symbol.kind, range=whole, selection_range=selection))
    return symbols


@server.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
def folding(ls: NcVerifyServer, params: types.FoldingRangeParams) -> list[types.FoldingRange]:
    return [types.FoldingRange(start_line=start, end_line=end) for start, end in sorted(set(ls.outline_of(params.text_document.uri).folds))]


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def definition(ls: NcVerifyServer, params: types.DefinitionParams) -> list[types.Location]:
    uri = params.text_document.uri
    found = ls.outline_of(uri)
    key = found.key_at(params.position.line, params.position.character)
    if key is None:
        return []
    places = found.definitions.get(key)
    if places:
        return [types.Location(uri=uri, range=place.range()) for place in places]
    return _in_other_files(ls, uri, key)


def _in_other_files(ls: NcVerifyServer, uri: str, key: str) -> list[types.Location]:
    """A called program that is not in the document: found on the subprogram search path
    (the document's folder first) as ``ncverify check`` finds it."""
    from ..library import SubprogramLibrary

    kind, _, name = key.partition(":") if ":" in key else (key[0], "", key[1:])
    if kind not in ("PGM", "O"):
        return []
    folders = [Path(to_fs_path(uri)).parent] if uri.startswith("file:") else []
    folders += list(ls.check_settings().subprogram_path)
    library = SubprogramLibrary(folders, ls.check_settings().extensions)
    source = library.find(name if kind == "PGM" else f"O{name}")
    if source is None or source.path is None:
        return []
    start = types.Position(line=0, character=0)
    return [types.Location(uri=source.path.resolve().as_uri(), range=types.Range(start=start, end=start))]


@server.feature(types.TEXT_DOCUMENT_REFERENCES)
def references(ls: NcVerifyServer, params: types.ReferenceParams) -> list[types.Location]:
    uri = params.text_document.uri
    found = ls.outline_of(uri)
    key = found.key_at(params.position.line, params.position.character)
    if key is None:
        return []
    places = list(found.references.get(key, []))
    if params.context.include_declaration:
        places += found.definitions.get(key, [])
    return [types.Location(uri=uri, range=place.range()) for place in sorted(places, key=lambda p: (p.line, p.start))]


def serve() -> None:
    """Run over stdin/stdout until the client sends ``exit`` or closes stdin."""
    import os

    if os.environ.get("NCVERIFY_LSP_LOG"):
        logging.basicConfig(filename=os.environ["NCVERIFY_LSP_LOG"], level=logging.DEBUG)
    try:
        server.start_io()
    finally:
        server.runner.cancel_all()
