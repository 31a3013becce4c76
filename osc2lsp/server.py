"""The language server's handlers: pygls handlers over the plain features of ``osc2lsp.features``.

Every handler is an adapter: find the snapshot (and the current text), turn
the client's position into an offset, call the feature, convert the result.
One guard (``transport.guard.guarded``) keeps any exception from escaping: it
logs the error, reports it to the client's log, and answers with an empty
result. Expected refusals (``Refusal``) and invalid params go back to the
client as errors.

The server object and what it owns are ``language_server.py``; documents and
their analyses are the session (``osc2lsp.session``); frames, params, serving and
the editor's watch are ``osc2lsp.transport``; the command line is ``cli.py``.

stdout carries JSON-RPC: nothing here may print; logging goes to stderr.
"""

from __future__ import annotations

import importlib
import logging
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from lsprotocol import types

from osc2lsp import convert
from osc2lsp.features import legend
from osc2lsp.language_server import Osc2LanguageServer
from osc2lsp.options import SECTION
from osc2lsp.session.view import View
from osc2lsp.text import LineIndex, uri_to_key
from osc2lsp.transport.guard import guarded
from osc2lsp.transport.protocol import Refusal

if TYPE_CHECKING:
    from osc2check.source import Span
    from osc2lsp.session.documents import LinesOf
    from osc2lsp.snapshot import Snapshot

    Find = Callable[[Snapshot, int], list[Span]]  # a feature answering with spans


class _Feature:
    """A feature module, imported on first use: the analysis it pulls in (lark, the
    checker, z3) is not needed to answer ``initialize``, so start-up stays short."""

    def __init__(self, name: str) -> None:
        self._name = f"osc2lsp.features.{name}"

    def __getattr__(self, attr: str) -> Any:
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


SERVER = Osc2LanguageServer()


# ---- lifecycle and documents --------------------------------------------------------


@SERVER.feature(types.INITIALIZE)
@guarded()
def initialize(ls: Osc2LanguageServer, params: types.InitializeParams) -> None:
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
async def initialized(ls: Osc2LanguageServer, params: types.InitializedParams) -> None:
    """Ask for the `osc2` settings (the grammar and the library are loading since the
    server started: ``main``)."""
    if ls.configuration:
        result = await ls.workspace_configuration_async(
            types.ConfigurationParams(items=[types.ConfigurationItem(section=SECTION)])
        )
        if result and isinstance(result[0], dict):
            ls.configure(result[0])


@SERVER.feature(types.SHUTDOWN)
@guarded()
async def shutdown(ls: Osc2LanguageServer, params: None) -> None:
    """Stop pending analyses."""
    await ls.state.shutdown()


@SERVER.feature(types.TEXT_DOCUMENT_DID_OPEN)
@guarded()
def did_open(ls: Osc2LanguageServer, params: types.DidOpenTextDocumentParams) -> None:
    """Analyse a document as soon as it opens."""
    doc = params.text_document
    ls.state.open(doc.uri, doc.text, doc.version)


@SERVER.feature(types.TEXT_DOCUMENT_DID_CHANGE)
@guarded()
def did_change(ls: Osc2LanguageServer, params: types.DidChangeTextDocumentParams) -> None:
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
def did_close(ls: Osc2LanguageServer, params: types.DidCloseTextDocumentParams) -> None:
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
) -> None:
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
async def document_diagnostic(
    ls: Osc2LanguageServer, params: types.DocumentDiagnosticParams
) -> types.RelatedFullDocumentDiagnosticReport | types.RelatedUnchangedDocumentDiagnosticReport:
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
async def complete(ls: Osc2LanguageServer, params: types.CompletionParams) -> types.CompletionList:
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
async def signature(
    ls: Osc2LanguageServer, params: types.SignatureHelpParams
) -> types.SignatureHelp | None:
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
    ls: Osc2LanguageServer, uri: str, position: types.Position, find: Find
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
async def on_hover(ls: Osc2LanguageServer, params: types.HoverParams) -> types.Hover | None:
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
async def definition(
    ls: Osc2LanguageServer, params: types.DefinitionParams
) -> list[types.Location]:
    """Where the name under the cursor is declared (also in the bundled library)."""
    uri = params.text_document.uri
    return await _located(ls, uri, params.position, navigation.definition)


@SERVER.feature(types.TEXT_DOCUMENT_TYPE_DEFINITION)
@guarded(list)
async def type_definition(
    ls: Osc2LanguageServer, params: types.TypeDefinitionParams
) -> list[types.Location]:
    """Where the type of the name or expression under the cursor is declared."""
    uri = params.text_document.uri
    return await _located(ls, uri, params.position, navigation.type_definition)


@SERVER.feature(types.TEXT_DOCUMENT_REFERENCES)
@guarded(list)
async def references(ls: Osc2LanguageServer, params: types.ReferenceParams) -> list[types.Location]:
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
async def highlight(
    ls: Osc2LanguageServer, params: types.DocumentHighlightParams
) -> list[types.DocumentHighlight]:
    """The uses of the symbol under the cursor in this document."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return []
    spans = navigation.highlights(snap, ls.offset(snap.lines, params.position))
    return convert.to_lsp_highlights(spans, snap.lines, ls.codec)


@SERVER.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
@guarded()
async def prepare_rename(
    ls: Osc2LanguageServer, params: types.PrepareRenameParams
) -> types.PrepareRenamePlaceholder | None:
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
async def on_rename(
    ls: Osc2LanguageServer, params: types.RenameParams
) -> types.WorkspaceEdit | None:
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
async def document_symbol(
    ls: Osc2LanguageServer, params: types.DocumentSymbolParams
) -> list[types.DocumentSymbol]:
    """Outline: declarations, members, phases and labels."""
    snap = await ls.state.fresh(params.text_document.uri)
    if snap is None:
        return []
    return convert.to_lsp_document_symbols(symbols.document_symbols(snap), snap.lines, ls.codec)


@SERVER.feature(types.WORKSPACE_SYMBOL)
@guarded(list)
def workspace_symbol(
    ls: Osc2LanguageServer, params: types.WorkspaceSymbolParams
) -> list[types.WorkspaceSymbol]:
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
async def tokens_full(
    ls: Osc2LanguageServer, params: types.SemanticTokensParams
) -> types.SemanticTokens:
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
async def tokens_range(
    ls: Osc2LanguageServer, params: types.SemanticTokensRangeParams
) -> types.SemanticTokens:
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
def folding_range(
    ls: Osc2LanguageServer, params: types.FoldingRangeParams
) -> list[types.FoldingRange]:
    """Blocks, comment runs and imports of the current text."""
    text, _ = ls.current(params.text_document.uri)
    return convert.to_lsp_folding_ranges(folding.folding_ranges(text))


@SERVER.feature(types.TEXT_DOCUMENT_INLAY_HINT)
@guarded(list)
async def inlay_hint(
    ls: Osc2LanguageServer, params: types.InlayHintParams
) -> list[types.InlayHint]:
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
async def code_action(
    ls: Osc2LanguageServer, params: types.CodeActionParams
) -> list[types.CodeAction]:
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
def format_document(
    ls: Osc2LanguageServer, params: types.DocumentFormattingParams
) -> list[types.TextEdit]:
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


def _lines_of(snap: Snapshot | None, others: list[Snapshot]) -> LinesOf:
    """Lines of any file one of the snapshots read."""
    snaps = ([snap] if snap is not None else []) + list(others)

    def lines_of(key: str) -> LineIndex | None:
        for s in snaps:
            found = s.lines_of(key)
            if found is not None:
                return found
        return None

    return lines_of
