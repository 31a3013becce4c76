"""The language server: pygls handlers over the plain features of ``osc2lsp.features``.

Every handler is an adapter: find the snapshot (and the current text), turn
the client's position into an offset, call the feature, convert the result.
One guard (``guarded``) keeps any exception from escaping: it logs the error,
reports it to the client's log, and answers with an empty result. Expected
refusals (``Refusal``) and invalid params go back to the client as errors.

Documents are kept by ``State`` with LSP's line semantics (``text.py``); the
JSON-RPC side (frames, params, shutdown) is ``protocol.py``. Whatever way the
server ends (``exit``, end of input, its editor gone, a signal), the solver
worker ends with it (``lifeline.py`` covers SIGKILL).

stdout carries JSON-RPC: nothing here may print; logging goes to stderr.
"""

from __future__ import annotations

import argparse
import asyncio
import functools
import gc
import importlib
import logging
import os
import signal
import sys
import threading
from collections.abc import Awaitable, Callable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, BinaryIO

from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.io_ import StdoutWriter
from pygls.lsp.server import LanguageServer

from osc2lsp import __version__, convert, lifeline
from osc2lsp.features import legend
from osc2lsp.options import SECTION, Options, from_settings
from osc2lsp.protocol import Osc2Protocol, Refusal, converter, serve, serve_stream
from osc2lsp.state import SWITCH, Findings, State
from osc2lsp.text import LineIndex, key_to_uri, uri_to_key
from osc2lsp.view import View

if TYPE_CHECKING:
    from osc2lsp.snapshot import Snapshot


class _Feature:
    """A feature module, imported on first use: the analysis it pulls in (lark, the
    checker, z3) is not needed to answer ``initialize``, so start-up stays short."""

    def __init__(self, name: str):
        self._name = f"osc2lsp.features.{name}"

    def __getattr__(self, attr: str):
        return getattr(importlib.import_module(self._name), attr)


code_actions = _Feature("code_actions")
completion = _Feature("completion")
diagnostics = _Feature("diagnostics")
folding = _Feature("folding")
formatting = _Feature("formatting")
hover = _Feature("hover")
inlay_hints = _Feature("inlay_hints")
navigation = _Feature("navigation")
rename = _Feature("rename")
semantic_tokens = _Feature("semantic_tokens")
signature_help = _Feature("signature_help")
symbols = _Feature("symbols")

log = logging.getLogger(__name__)

COMPLETION_TRIGGERS = [".", "@", "(", ","]
SIGNATURE_TRIGGERS = ["(", ","]


class Osc2LanguageServer(LanguageServer):
    """pygls server holding the open documents' state and the client's abilities."""

    def __init__(self) -> None:
        super().__init__(
            "osc2lsp", __version__, protocol_cls=Osc2Protocol, converter_factory=converter
        )
        self.state = State(Options(), self.publish)
        self.pull = False  # the client pulls diagnostics (textDocument/diagnostic)
        self.refresh = False  # ... and accepts workspace/diagnostic/refresh
        self.configuration = False  # the client answers workspace/configuration
        self._stop: asyncio.Event | None = None
        self._loop: asyncio.AbstractEventLoop | None = None

    # ---- helpers used by the handlers ----------------------------------------------

    @property
    def codec(self):
        return self.workspace.position_codec

    @property
    def options(self) -> Options:
        return self.state.options

    def library(self, uri: str) -> bool:
        """Whether ``uri`` is an open file of the bundled library (read-only here)."""
        doc = self.state.documents.get(uri)
        return doc is not None and doc.library

    def uri_of(self, key: str) -> str:
        for doc in self.state.documents.values():
            if doc.key == key:
                return doc.uri
        return key_to_uri(key)

    def current(self, uri: str) -> tuple[str, LineIndex]:
        """The document's text now and its lines (a closed file is read from disk; an
        unknown one is empty)."""
        doc = self.state.documents.get(uri)
        if doc is not None:
            return doc.text, doc.lines
        if not uri.startswith("file:"):
            return "", LineIndex("")
        try:
            text = Path(uri_to_key(uri)).read_text(encoding="utf-8", errors="replace")
        except OSError:
            text = ""
        return text, LineIndex(text)

    def offset(self, lines: LineIndex, position: types.Position) -> int:
        return convert.from_lsp_position(lines, position, self.codec)

    def publish(self, trigger: str, found: list[Findings]) -> None:
        """Send findings the client does not have: pushed, or a refresh request to a
        pulling client that holds older ones (its own document's next version it pulls
        by itself)."""
        if self.pull:
            if self.refresh and any(self._outdated(f, trigger) for f in found):
                self.workspace_diagnostic_refresh(None)
            return
        for f in found:
            items = convert.to_lsp_diagnostics(
                f.lines_of, f.diagnostics, self.uri_of, self.codec, self.options.docs_url
            )
            self.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(uri=f.uri, diagnostics=items, version=f.version)
            )
            self.state.pushed(f)

    def _outdated(self, found: Findings, trigger: str) -> bool:
        """Whether a pulling client holds other findings for ``found``'s version."""
        if not found.final:
            return False
        doc = self.state.documents.get(found.uri)
        pulled = doc.delivered if doc is not None else None
        return (
            found.uri != trigger
            or found.verified
            or (pulled is not None and pulled[0] == found.version)
        )

    def configure(self, settings, refresh: bool = True) -> None:
        """Apply the client's `osc2` settings; re-check every document (and ask the
        client to re-request inlay hints when ``refresh`` and they changed)."""
        log.debug("settings: %r", settings)
        previous = self.options
        options, problems = from_settings(settings, previous)
        for problem in problems:
            self.window_show_message(
                types.ShowMessageParams(
                    type=types.MessageType.Warning, message=f"osc2lsp: {problem}"
                )
            )
        self.state.reconfigure(options)
        workspace = self.client_capabilities.workspace
        if (
            refresh
            and options.inlay_hints != previous.inlay_hints
            and workspace
            and workspace.inlay_hint
            and workspace.inlay_hint.refresh_support
        ):
            self.workspace_inlay_hint_refresh(None)

    def report_server_error(self, error: Exception, source) -> None:
        log.error("server error (%s): %s", getattr(source, "__name__", source), error)

    # ---- running ---------------------------------------------------------------------

    def start_io(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> None:
        """Serve over stdio until ``exit``, end of input, or the editor's end."""
        self.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))
        assert isinstance(self.protocol, Osc2Protocol)
        self._run(functools.partial(serve, self.protocol, stdin or sys.stdin.buffer))

    def start_tcp(self, host: str, port: int) -> None:
        """Serve the first client to connect on ``host``:``port`` until ``exit``, the
        end of its connection, or the editor's end (one client per server, as pygls)."""
        self._run(functools.partial(self._serve_connection, host, port))

    async def _serve_connection(self, host: str, port: int) -> None:
        loop = asyncio.get_running_loop()
        connected: asyncio.Future[tuple[asyncio.StreamReader, asyncio.StreamWriter]]
        connected = loop.create_future()

        def accept(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            if connected.done():
                log.warning("a second client connected: refused (one client per server)")
                writer.close()
                return
            connected.set_result((reader, writer))

        try:
            listening = await asyncio.start_server(accept, host, port)
        except OSError as exc:  # a port in use, an unknown host
            print(f"osc2lsp: cannot listen on {host}:{port}: {exc.strerror}", file=sys.stderr)
            raise SystemExit(2) from None
        addresses = ", ".join(str(s.getsockname()) for s in listening.sockets)
        log.info("serving on %s", addresses)
        try:
            reader, writer = await connected
        finally:
            listening.close()
        self.protocol.set_writer(writer)
        assert isinstance(self.protocol, Osc2Protocol)
        try:
            await serve_stream(self.protocol, reader)
        finally:
            writer.close()

    def _run(self, reading: Callable[[], Awaitable[None]]) -> None:
        """Run ``reading`` (it reads and dispatches frames) until it ends, ``exit``, a
        signal or the editor's end; then leave with ``exit``'s code."""
        self._stop_event = threading.Event()
        code = 0
        try:
            asyncio.run(self._serve(reading))
        except SystemExit as exc:  # `exit`: pygls answers it with sys.exit
            code = exc.code if isinstance(exc.code, int) else 0
        except KeyboardInterrupt:
            code = 130
        finally:
            self.state.kill()  # if `shutdown` never came
        sys.exit(code)

    async def _serve(self, reading: Callable[[], Awaitable[None]]) -> None:
        self._stop = asyncio.Event()
        frames = asyncio.ensure_future(reading())
        stopping = asyncio.ensure_future(self._stop.wait())
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGTERM, signal.SIGHUP) if sys.platform != "win32" else ():
            loop.add_signal_handler(sig, self._stop.set)
        try:
            await asyncio.wait({frames, stopping}, return_when=asyncio.FIRST_COMPLETED)
            if frames.done():
                frames.result()  # SystemExit from `exit` surfaces here
        finally:
            for task in (frames, stopping):
                task.cancel()
            await self.state.shutdown()

    def stop(self) -> None:
        """Stop serving (from any thread): the editor is gone."""
        loop, stop = self._loop, self._stop
        if loop is not None and stop is not None:
            loop.call_soon_threadsafe(stop.set)

    def watch_editor(self, pid: int | None) -> None:
        """Stop when process ``pid`` (the editor, from ``initialize``) ends."""
        if pid is None or pid == os.getpid() or not lifeline.alive(pid):
            return
        self._loop = asyncio.get_running_loop()
        lifeline.watch(lambda: not lifeline.alive(pid), self.stop, 2.0, "osc2lsp-editor-watch")


SERVER = Osc2LanguageServer()


def guarded(default=None):
    """Log any exception of a handler and answer ``default()`` (or ``default``)."""

    def empty():
        return default() if callable(default) else default

    def wrap(fn):
        def report(ls):
            log.exception("%s failed", fn.__name__)
            try:
                ls.window_log_message(
                    types.LogMessageParams(
                        type=types.MessageType.Error,
                        message=f"osc2lsp: internal error in {fn.__name__} (see the server log)",
                    )
                )
            except Exception:  # the transport itself may be gone
                pass

        if asyncio.iscoroutinefunction(fn):

            @functools.wraps(fn)
            async def run_async(ls, params):
                try:
                    return await fn(ls, params)
                except (asyncio.CancelledError, JsonRpcException):
                    raise
                except Exception:
                    report(ls)
                    return empty()

            return run_async

        @functools.wraps(fn)
        def run(ls, params):
            try:
                return fn(ls, params)
            except JsonRpcException:
                raise
            except Exception:
                report(ls)
                return empty()

        return run

    return wrap


# ---- lifecycle and documents --------------------------------------------------------


@SERVER.feature(types.INITIALIZE)
@guarded()
def initialize(ls: Osc2LanguageServer, params: types.InitializeParams):
    """Read the client's abilities and initialization options."""
    caps = params.capabilities
    ls.pull = bool(caps.text_document and caps.text_document.diagnostic is not None)
    workspace = caps.workspace
    ls.refresh = bool(workspace and workspace.diagnostics and workspace.diagnostics.refresh_support)
    ls.configuration = bool(workspace and workspace.configuration)
    root = params.root_uri or (
        params.workspace_folders[0].uri if params.workspace_folders else None
    )
    ls.state.root = uri_to_key(root) if root else None
    if params.initialization_options:
        ls.configure(params.initialization_options, refresh=False)
    ls.watch_editor(params.process_id)


@SERVER.feature(types.INITIALIZED)
@guarded()
async def initialized(ls: Osc2LanguageServer, params: types.InitializedParams):
    """Ask for the `osc2` settings (the grammar and the library are loading since the
    server started: ``main``)."""
    if ls.configuration:
        result = await ls.workspace_configuration_async(
            types.ConfigurationParams(items=[types.ConfigurationItem(section=SECTION)])
        )
        if result and isinstance(result[0], dict):
            ls.configure(result[0])


def _warm_up() -> None:
    """Load the grammar and the library, then exempt them from garbage collection.

    It runs on the analysis thread from the moment the server starts, ahead of the
    first analysis (the client's `initialize` is answered meanwhile): ``gc.freeze``
    keeps whatever exists at that moment forever, and a document's analysis frozen
    by mistake would never be freed.
    """
    from osc2check.semantics.stdlib import standard_library
    from osc2check.syntax.tables import parse_tables

    parse_tables()
    standard_library()
    completion.complete(None, "scenario s:\n    ", 16)  # the grammar table, the focus path
    importlib.import_module("osc2lsp.preview")  # what the first edit needs
    # the library and the grammar live as long as the process: never scan them. No
    # collection first: it finds a few dozen objects of garbage after all this (measured:
    # 54) and costs a full scan of the library, on the way to the first diagnostics
    gc.freeze()


@SERVER.feature(types.SHUTDOWN)
@guarded()
async def shutdown(ls: Osc2LanguageServer, params):
    """Stop pending analyses."""
    await ls.state.shutdown()


@SERVER.feature(types.TEXT_DOCUMENT_DID_OPEN)
@guarded()
def did_open(ls: Osc2LanguageServer, params: types.DidOpenTextDocumentParams):
    """Analyse a document as soon as it opens."""
    doc = params.text_document
    ls.state.open(doc.uri, doc.text, doc.version)


@SERVER.feature(types.TEXT_DOCUMENT_DID_CHANGE)
@guarded()
def did_change(ls: Osc2LanguageServer, params: types.DidChangeTextDocumentParams):
    """Apply the edits (lines end only at CR LF, LF and CR); re-analyse after the debounce."""
    uri = params.text_document.uri
    doc = ls.state.documents.get(uri)
    text, lines = (doc.text, doc.lines) if doc is not None else ls.current(uri)
    for change in params.content_changes:
        if isinstance(change, types.TextDocumentContentChangePartial):
            start = ls.offset(lines, change.range.start)
            end = max(start, ls.offset(lines, change.range.end))
            lines = lines.edited(start, end, change.text)
        else:
            lines = LineIndex(change.text)
    if doc is not None and doc.library and lines.text != doc.text:
        log.info("%s is a file of the bundled library: its edits are not analysed", uri)
    ls.state.change(uri, lines.text, params.text_document.version, lines)


@SERVER.feature(types.TEXT_DOCUMENT_DID_CLOSE)
@guarded()
def did_close(ls: Osc2LanguageServer, params: types.DidCloseTextDocumentParams):
    """Forget the document and clear its pushed diagnostics."""
    uri = params.text_document.uri
    library = ls.library(uri)
    ls.state.close(uri)
    if not ls.pull and not library:
        ls.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, diagnostics=[])
        )


@SERVER.feature(types.WORKSPACE_DID_CHANGE_CONFIGURATION)
@guarded()
async def did_change_configuration(
    ls: Osc2LanguageServer, params: types.DidChangeConfigurationParams
):
    """Apply new `osc2` settings (sent along, or asked for) and re-check everything."""
    settings = params.settings
    if isinstance(settings, dict) and SECTION in settings:
        ls.configure(settings)
    elif ls.configuration:
        result = await ls.workspace_configuration_async(
            types.ConfigurationParams(items=[types.ConfigurationItem(section=SECTION)])
        )
        ls.configure(result[0] if result and isinstance(result[0], dict) else {})


# ---- diagnostics ---------------------------------------------------------------------


@SERVER.feature(
    types.TEXT_DOCUMENT_DIAGNOSTIC,
    types.DiagnosticOptions(
        identifier="osc2", inter_file_dependencies=True, workspace_diagnostics=False
    ),
)
@guarded()
async def document_diagnostic(ls: Osc2LanguageServer, params: types.DocumentDiagnosticParams):
    """Pulled diagnostics of the current version."""
    uri = params.text_document.uri
    found = await ls.state.findings_now(uri, preview=ls.refresh)
    if found is None:
        return types.RelatedFullDocumentDiagnosticReport(items=[])
    ls.state.delivered(uri, found)
    result_id = diagnostics.result_id(found.diagnostics)
    if params.previous_result_id == result_id:
        return types.RelatedUnchangedDocumentDiagnosticReport(result_id=result_id)
    items = convert.to_lsp_diagnostics(
        found.lines_of, found.diagnostics, ls.uri_of, ls.codec, ls.options.docs_url
    )
    return types.RelatedFullDocumentDiagnosticReport(items=items, result_id=result_id)


# ---- typing: completion and signature help (current text, latest snapshot) ------------


@SERVER.feature(
    types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=COMPLETION_TRIGGERS)
)
@guarded()
async def complete(ls: Osc2LanguageServer, params: types.CompletionParams):
    """Completion from the grammar state and the names around the cursor."""
    uri = params.text_document.uri
    text, lines = ls.current(uri)
    snap = ls.state.latest(uri) or await ls.state.fresh(uri)
    result = completion.complete(
        snap, text, ls.offset(lines, params.position), ls.options.completion_limit
    )
    return convert.to_lsp_completion(result, lines, ls.codec)


@SERVER.feature(
    types.TEXT_DOCUMENT_SIGNATURE_HELP,
    types.SignatureHelpOptions(trigger_characters=SIGNATURE_TRIGGERS),
)
@guarded()
async def signature(ls: Osc2LanguageServer, params: types.SignatureHelpParams):
    """Parameters of the invocation being written."""
    uri = params.text_document.uri
    text, lines = ls.current(uri)
    snap = ls.state.latest(uri) or await ls.state.fresh(uri)
    result = signature_help.signature_help(snap, text, ls.offset(lines, params.position))
    return convert.to_lsp_signature_help(result)


# ---- reading: hover, navigation, symbols (fresh snapshot) -------------------------------


async def _view_at(
    ls: Osc2LanguageServer, uri: str, position: types.Position, fresh: bool = False
) -> tuple[View, int] | None:
    """The view to answer about ``position`` of the current text, and its offset there
    (``fresh``: the current version's analysis, waiting for it if need be)."""
    text, lines = ls.current(uri)
    offset = ls.offset(lines, position)
    found = ls.state.view_now(uri, offset) if not fresh else None
    if found is None:
        snap = await ls.state.fresh(uri)
        if snap is None:
            return None
        found = (snap, None)
    snap, change = found
    if change is None:
        same = snap.text is text or snap.text == text
        return View(snap, None, snap.lines), offset if same else ls.offset(snap.lines, position)
    old = change.to_old(offset)
    return View(snap, change, lines), old if old is not None else offset


async def _located(
    ls: Osc2LanguageServer, uri: str, position: types.Position, find
) -> list[types.Location]:
    """Locations ``find(snapshot, offset)`` gives, from the latest analysis when they lie
    outside the text edited since, else from the current version's."""
    found = await _view_at(ls, uri, position)
    if found is None:
        return []
    view, offset = found
    spans = find(view.snap, offset)
    moved = view.spans(spans)
    if len(moved) < len(spans):  # it points into the edited text: ask the current version
        found = await _view_at(ls, uri, position, fresh=True)
        if found is None:
            return []
        view, offset = found
        moved = view.spans(find(view.snap, offset))
    return convert.to_lsp_locations(moved, view.lines_of, ls.uri_of, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_HOVER)
@guarded()
async def on_hover(ls: Osc2LanguageServer, params: types.HoverParams):
    """Declaration, type, value or code documentation under the cursor."""
    found = await _view_at(ls, params.text_document.uri, params.position)
    if found is None:
        return None
    view, offset = found
    result = hover.hover(view.snap, offset)
    if result is not None and result.span is not None:
        result = replace(result, span=view.span(result.span))
    return convert.to_lsp_hover(result, view.lines, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_DEFINITION)
@guarded(list)
async def definition(ls: Osc2LanguageServer, params: types.DefinitionParams):
    """Where the name under the cursor is declared (also in the bundled library)."""
    uri = params.text_document.uri
    return await _located(ls, uri, params.position, navigation.definition)


@SERVER.feature(types.TEXT_DOCUMENT_TYPE_DEFINITION)
@guarded(list)
async def type_definition(ls: Osc2LanguageServer, params: types.TypeDefinitionParams):
    """Where the type of the name or expression under the cursor is declared."""
    uri = params.text_document.uri
    return await _located(ls, uri, params.position, navigation.type_definition)


@SERVER.feature(types.TEXT_DOCUMENT_REFERENCES)
@guarded(list)
async def references(ls: Osc2LanguageServer, params: types.ReferenceParams):
    """Every use of the symbol under the cursor in the open documents' programs."""
    uri = params.text_document.uri
    snap = await ls.state.fresh(uri)
    if snap is None:
        return []
    offset = ls.offset(snap.lines, params.position)
    others = await _other_snapshots(ls, snap, offset)
    spans = navigation.references(snap, offset, params.context.include_declaration, others)
    return convert.to_lsp_locations(spans, _lines_of(snap, others), ls.uri_of, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
@guarded(list)
async def highlight(ls: Osc2LanguageServer, params: types.DocumentHighlightParams):
    """The uses of the symbol under the cursor in this document."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return []
    spans = navigation.highlights(snap, ls.offset(snap.lines, params.position))
    return convert.to_lsp_highlights(spans, snap.lines, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
@guarded()
async def prepare_rename(ls: Osc2LanguageServer, params: types.PrepareRenameParams):
    """The range to rename, or why the name cannot be renamed."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return None
    if ls.library(params.text_document.uri):
        raise Refusal("the bundled library is read-only")
    try:
        span, text = rename.prepare_rename(snap, ls.offset(snap.lines, params.position))
    except rename.RenameError as exc:
        raise Refusal(str(exc)) from None
    return types.PrepareRenamePlaceholder(
        range=convert.to_lsp_range(span, snap.lines, ls.codec), placeholder=text
    )


@SERVER.feature(types.TEXT_DOCUMENT_RENAME)
@guarded()
async def on_rename(ls: Osc2LanguageServer, params: types.RenameParams):
    """Rename a declaration and its uses across the open documents' programs."""
    uri = params.text_document.uri
    snap = await ls.state.fresh(uri)
    if snap is None:
        return None
    if ls.library(uri):
        raise Refusal("the bundled library is read-only")
    offset = ls.offset(snap.lines, params.position)
    others = await _other_snapshots(ls, snap, offset)
    try:
        edits = rename.rename(snap, offset, params.new_name, others)
    except rename.RenameError as exc:
        raise Refusal(str(exc)) from None
    return convert.to_lsp_workspace_edit(edits, _lines_of(snap, others), ls.uri_of, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
@guarded(list)
async def document_symbol(ls: Osc2LanguageServer, params: types.DocumentSymbolParams):
    """Outline: declarations, members, phases and labels."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return []
    return convert.to_lsp_document_symbols(symbols.document_symbols(snap), snap.lines, ls.codec)


@SERVER.feature(types.WORKSPACE_SYMBOL)
@guarded(list)
def workspace_symbol(ls: Osc2LanguageServer, params: types.WorkspaceSymbolParams):
    """Declarations of the open documents and of the library matching the query."""
    snaps = [
        d.snapshot
        for d in ls.state.documents.values()
        if d.snapshot is not None and not d.library  # the library's symbols come anyway
    ]
    found = symbols.workspace_symbols(snaps, params.query)
    return convert.to_lsp_workspace_symbols(found, _lines_of(None, snaps), ls.uri_of, ls.codec)


@SERVER.feature(
    types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
    types.SemanticTokensLegend(
        token_types=legend.TOKEN_TYPES, token_modifiers=legend.TOKEN_MODIFIERS
    ),
)
@guarded()
async def tokens_full(ls: Osc2LanguageServer, params: types.SemanticTokensParams):
    """What each name is: actor, action, modifier, parameter, unit, event..."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return types.SemanticTokens(data=[])
    return convert.to_lsp_semantic_tokens(
        semantic_tokens.semantic_tokens(snap), snap.lines, ls.codec
    )


@SERVER.feature(
    types.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE,
    types.SemanticTokensLegend(
        token_types=legend.TOKEN_TYPES, token_modifiers=legend.TOKEN_MODIFIERS
    ),
)
@guarded()
async def tokens_range(ls: Osc2LanguageServer, params: types.SemanticTokensRangeParams):
    """Semantic tokens of a range."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return types.SemanticTokens(data=[])
    start = ls.offset(snap.lines, params.range.start)
    end = ls.offset(snap.lines, params.range.end)
    return convert.to_lsp_semantic_tokens(
        semantic_tokens.semantic_tokens(snap, start, end), snap.lines, ls.codec
    )


@SERVER.feature(types.TEXT_DOCUMENT_FOLDING_RANGE)
@guarded(list)
def folding_range(ls: Osc2LanguageServer, params: types.FoldingRangeParams):
    """Blocks, comment runs and imports of the current text."""
    text, _ = ls.current(params.text_document.uri)
    return convert.to_lsp_folding_ranges(folding.folding_ranges(text))


@SERVER.feature(types.TEXT_DOCUMENT_INLAY_HINT)
@guarded(list)
async def inlay_hint(ls: Osc2LanguageServer, params: types.InlayHintParams):
    """Folded physical values and parameter names, when the setting enables them."""
    hints_options = ls.options.inlay_hints
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None or not hints_options.enabled:
        return []
    start = ls.offset(snap.lines, params.range.start)
    end = ls.offset(snap.lines, params.range.end)
    found = inlay_hints.inlay_hints(
        snap, start, end, hints_options.values, hints_options.parameter_names
    )
    return convert.to_lsp_inlay_hints(found, snap.lines, ls.codec)


@SERVER.feature(
    types.TEXT_DOCUMENT_CODE_ACTION,
    types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]),
)
@guarded(list)
async def code_action(ls: Osc2LanguageServer, params: types.CodeActionParams):
    """Quick fixes: the checker's suggestions, a missing import, a suppression."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None or ls.library(params.text_document.uri):
        return []
    start = ls.offset(snap.lines, params.range.start)
    end = ls.offset(snap.lines, params.range.end)
    actions = code_actions.code_actions(snap, start, end)
    return convert.to_lsp_code_actions(actions, snap, ls.uri_of, ls.codec, ls.options.docs_url)


@SERVER.feature(types.TEXT_DOCUMENT_FORMATTING)
@guarded(list)
def format_document(ls: Osc2LanguageServer, params: types.DocumentFormattingParams):
    """Indentation (the file's own unit, whatever the client's options) and spacing;
    nothing when the file has syntax errors or belongs to the bundled library."""
    uri = params.text_document.uri
    text, lines = ls.current(uri)
    if ls.library(uri):
        return []
    formatted = formatting.format_in_own_style(text)
    if formatted is None or formatted == text:
        return []
    return convert.to_lsp_format_edits(text, formatted, lines)


async def _other_snapshots(ls: Osc2LanguageServer, snap: Snapshot, offset: int) -> list[Snapshot]:
    """The other open documents, and the workspace's closed files that mention the
    name at ``offset``: where references to it may be."""
    others = [s for s in await ls.state.fresh_all() if s.uri != snap.uri]
    entry = snap.name_at(offset)
    if entry is not None:
        others += await ls.state.closed_files(entry.name.text)
    return others


def _lines_of(snap: Snapshot | None, others: list[Snapshot]):
    """Lines of any file one of the snapshots read."""
    snaps = ([snap] if snap is not None else []) + list(others)

    def lines_of(key: str):
        for s in snaps:
            found = s.lines_of(key)
            if found is not None:
                return found
        return None

    return lines_of


# ---- entry point ------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    """``osc2lsp [--tcp [--host H] [--port P]] [--log-level L] [--log-file F]``."""
    parser = argparse.ArgumentParser(
        prog="osc2lsp", description="Language server for ASAM OpenSCENARIO DSL 2.x"
    )
    parser.add_argument(
        "--tcp",
        action="store_true",
        help="serve the first client to connect on TCP instead of stdio",
    )
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=2087)
    parser.add_argument(
        "--log-level",
        default=os.environ.get("OSC2LSP_LOG_LEVEL", "WARNING"),
        choices=["DEBUG", "INFO", "WARNING", "ERROR"],
    )
    parser.add_argument("--log-file", help="log here instead of to stderr")
    parser.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the start-up cache (the parser's tables, the analysed "
        "standard library; OSC2_CACHE_DIR says where it is)",
    )
    parser.add_argument("--version", action="version", version=f"osc2lsp {__version__}")
    args = parser.parse_args(argv)
    if args.no_cache:
        from osc2check import cache

        cache.set_enabled(False)
    handler = (
        logging.FileHandler(args.log_file) if args.log_file else logging.StreamHandler(sys.stderr)
    )
    logging.basicConfig(
        level=args.log_level,
        handlers=[handler],
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    # Analyses make many long-lived objects; collect young ones less often so that a
    # collection does not land in the middle of a keystroke's request.
    gc.set_threshold(20_000, 20, 50)
    # The analysis thread gives way to requests quickly (see state.SWITCH).
    sys.setswitchinterval(SWITCH)
    # the grammar, the library and the analysis's modules load while the client and the
    # server say hello: the first analysis, queued behind this, needs them all
    SERVER.state.executor.submit(_warm_up)
    if args.tcp:
        SERVER.start_tcp(args.host, args.port)
    else:
        SERVER.start_io()
    return 0
