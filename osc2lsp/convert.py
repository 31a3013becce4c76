"""The one place where positions and results cross between osc2check and LSP.

osc2check counts 1-based lines and columns in code points; LSP counts 0-based
lines and columns in the units the client negotiated (UTF-16 unless it asked
for UTF-8 or UTF-32). ``from_lsp_*`` functions turn client positions into
code-point offsets of a text; ``to_lsp_*`` functions turn spans, diagnostics
and feature results into lsprotocol types, using the text of the file each
span points into.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable, Iterable
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

import osc2check
from osc2check import rules
from osc2check.codes import Code, Severity
from osc2check.diagnostics import Diagnostic, TextEdit
from osc2check.source import Span
from osc2lsp.text import LineIndex, key_to_uri

if TYPE_CHECKING:  # the features import the analysis; this module stays cheap to import
    from osc2lsp.features.code_actions import Action
    from osc2lsp.features.completion import Candidate, CompletionResult
    from osc2lsp.features.folding import Fold
    from osc2lsp.features.hover import HoverResult
    from osc2lsp.features.inlay_hints import Hint
    from osc2lsp.features.semantic_tokens import SemanticToken
    from osc2lsp.features.signature_help import SignatureResult
    from osc2lsp.features.symbols import DocSymbol, WorkspaceSymbol
    from osc2lsp.snapshot import Snapshot

LinesOf = Callable[[str], LineIndex | None]  # file key → its lines
UriOf = Callable[[str], str]  # file key → client URI

_SEVERITY = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}
_UNNECESSARY = frozenset({"S001"})
_COMPLETION_KINDS = {
    "keyword": types.CompletionItemKind.Keyword,
    "field": types.CompletionItemKind.Field,
    "variable": types.CompletionItemKind.Variable,
    "method": types.CompletionItemKind.Method,
    "action": types.CompletionItemKind.Function,
    "scenario": types.CompletionItemKind.Function,
    "modifier": types.CompletionItemKind.Function,
    "event": types.CompletionItemKind.Event,
    "unit": types.CompletionItemKind.Unit,
    "enum_member": types.CompletionItemKind.EnumMember,
    "type": types.CompletionItemKind.Class,
    "argument": types.CompletionItemKind.Property,
    "label": types.CompletionItemKind.Reference,
    "module": types.CompletionItemKind.Module,
    "function": types.CompletionItemKind.Function,
}
_SYMBOL_KINDS = {
    "scenario": types.SymbolKind.Class,
    "actor": types.SymbolKind.Class,
    "struct": types.SymbolKind.Struct,
    "action": types.SymbolKind.Function,
    "modifier": types.SymbolKind.Function,
    "enum": types.SymbolKind.Enum,
    "enum_member": types.SymbolKind.EnumMember,
    "type": types.SymbolKind.TypeParameter,
    "unit": types.SymbolKind.Constant,
    "field": types.SymbolKind.Field,
    "variable": types.SymbolKind.Variable,
    "event": types.SymbolKind.Event,
    "method": types.SymbolKind.Method,
    "label": types.SymbolKind.Key,
    "do": types.SymbolKind.Namespace,
    "namespace": types.SymbolKind.Namespace,
    "extend": types.SymbolKind.Class,
    "global": types.SymbolKind.Constant,
}


# ---- positions ------------------------------------------------------------------


def client_units(text: str, codec: PositionCodec) -> int:
    """How many of the client's units (UTF-8 bytes, UTF-16 code units or code points)
    ``text`` takes."""
    encoding = codec.encoding
    if encoding == types.PositionEncodingKind.Utf32 or text.isascii():
        return len(text)
    if encoding == types.PositionEncodingKind.Utf8:
        return len(text.encode("utf-8", "surrogatepass"))
    return len(text.encode("utf-16-le", "surrogatepass")) // 2


def _column(content: str, units: int, codec: PositionCodec) -> int:
    """The code-point column ``units`` client units into ``content``; past the end of the
    line it is the line's length (LSP's rule), inside a character its end."""
    if codec.encoding == types.PositionEncodingKind.Utf32 or content.isascii():
        return max(0, min(units, len(content)))
    count = 0
    for column, ch in enumerate(content):
        if count >= units:
            return column
        count += client_units(ch, codec)
    return len(content)


def from_lsp_position(lines: LineIndex, position: types.Position, codec: PositionCodec) -> int:
    """The code-point offset in ``lines``' text of a client position."""
    line = position.line
    if line >= len(lines):
        return len(lines.text)
    content = lines.line_content(line)
    return lines.offset(line, _column(content, position.character, codec))


def to_lsp_position(lines: LineIndex, offset: int, codec: PositionCodec) -> types.Position:
    line, column = lines.position(offset)
    content = lines.line_content(line)
    return types.Position(line=line, character=client_units(content[:column], codec))


def to_lsp_range(span: Span, lines: LineIndex | None, codec: PositionCodec) -> types.Range:
    """A span as a client range; without the file's text, columns are taken as is."""
    if lines is None:
        return types.Range(
            start=types.Position(line=max(span.line - 1, 0), character=max(span.column - 1, 0)),
            end=types.Position(
                line=max(span.end_line - 1, 0), character=max(span.end_column - 1, 0)
            ),
        )
    return types.Range(
        start=_line_column(lines, span.line, span.column, codec),
        end=_line_column(lines, span.end_line, span.end_column, codec),
    )


def _line_column(lines: LineIndex, line: int, column: int, codec: PositionCodec) -> types.Position:
    line0 = max(line - 1, 0)
    if line0 >= len(lines):
        return types.Position(line=len(lines), character=0)
    content = lines.line_content(line0)
    column0 = min(max(column - 1, 0), len(content))
    return types.Position(line=line0, character=client_units(content[:column0], codec))


def offsets_to_lsp_range(
    lines: LineIndex, start: int, end: int, codec: PositionCodec
) -> types.Range:
    return types.Range(
        start=to_lsp_position(lines, start, codec), end=to_lsp_position(lines, end, codec)
    )


def to_lsp_location(
    span: Span, lines_of: LinesOf, uri_of: UriOf, codec: PositionCodec
) -> types.Location:
    return types.Location(uri=uri_of(span.uri), range=to_lsp_range(span, lines_of(span.uri), codec))


# ---- diagnostics ----------------------------------------------------------------


@cache
def docs_href(code: Code, docs_url: str = "") -> str:
    """The address of a code's section of ``docs/checks.md`` (``rules.doc_url``): under
    ``docs_url`` when the client set one, else the checkout's file, else the code's page
    inside the installed package."""
    anchor = rules.anchor(code)
    if docs_url:
        return f"{docs_url.split('#')[0]}#{anchor}"
    package = Path(osc2check.__file__).resolve().parent
    checks = package.parent / rules.doc_url(code).split("#")[0]
    if checks.is_file():
        return f"{checks.as_uri()}#{anchor}"
    return (package / "code_docs" / f"{code.code}.md").as_uri()


def to_lsp_diagnostic(
    d: Diagnostic, lines_of: LinesOf, uri_of: UriOf, codec: PositionCodec, docs_url: str = ""
) -> types.Diagnostic:
    related = [
        types.DiagnosticRelatedInformation(
            location=to_lsp_location(r.span, lines_of, uri_of, codec), message=r.message
        )
        for r in d.related
    ]
    data: dict[str, Any] = {"code": d.code.code}
    if d.data.get("suggestion"):
        data["suggestion"] = d.data["suggestion"]
    if d.fix is not None:
        data["fix"] = {"message": d.fix.message, "safe": d.fix.safe}
    return types.Diagnostic(
        range=to_lsp_range(d.span, lines_of(d.span.uri), codec),
        message=d.message,
        severity=_SEVERITY.get(d.severity, types.DiagnosticSeverity.Error),
        code=d.code.code,
        code_description=types.CodeDescription(href=docs_href(d.code, docs_url)),
        source="osc2check",
        related_information=related or None,
        tags=[types.DiagnosticTag.Unnecessary] if d.code.code in _UNNECESSARY else None,
        data=data,
    )


def to_lsp_diagnostics(
    lines_of: LinesOf,
    diagnostics: Iterable[Diagnostic],
    uri_of: UriOf,
    codec: PositionCodec,
    docs_url: str = "",
) -> list[types.Diagnostic]:
    """Diagnostics as the client wants them; ``lines_of`` gives the text of each file
    they point into (``Snapshot.lines_of``, or a preview's)."""
    return [to_lsp_diagnostic(d, lines_of, uri_of, codec, docs_url) for d in diagnostics]


# ---- feature results ------------------------------------------------------------


def to_lsp_hover(
    result: HoverResult | None, lines: LineIndex, codec: PositionCodec
) -> types.Hover | None:
    if result is None:
        return None
    rng = to_lsp_range(result.span, lines, codec) if result.span is not None else None
    return types.Hover(
        contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=result.markdown),
        range=rng,
    )


def to_lsp_completion(
    result: CompletionResult, lines: LineIndex, codec: PositionCodec, snippets: bool = False
) -> types.CompletionList:
    rng = offsets_to_lsp_range(lines, result.start, result.end, codec)
    items = [_completion_item(c, rng, i) for i, c in enumerate(result.items)]
    return types.CompletionList(is_incomplete=result.incomplete, items=items)


def _completion_item(c: Candidate, rng: types.Range, index: int) -> types.CompletionItem:
    text = c.insert_text if c.insert_text is not None else c.label
    return types.CompletionItem(
        label=c.label,
        kind=_COMPLETION_KINDS.get(c.kind, types.CompletionItemKind.Text),
        detail=c.detail or None,
        documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=c.documentation)
        if c.documentation
        else None,
        sort_text=f"{c.group}{index:04d}",
        filter_text=c.label,
        text_edit=types.TextEdit(range=rng, new_text=text),
    )


def to_lsp_locations(
    spans: list[Span], lines_of: LinesOf, uri_of: UriOf, codec: PositionCodec
) -> list[types.Location]:
    return [to_lsp_location(s, lines_of, uri_of, codec) for s in spans]


def to_lsp_highlights(
    spans: list[Span], lines: LineIndex, codec: PositionCodec
) -> list[types.DocumentHighlight]:
    return [
        types.DocumentHighlight(
            range=to_lsp_range(s, lines, codec), kind=types.DocumentHighlightKind.Text
        )
        for s in spans
    ]


def to_lsp_workspace_edit(
    edits: dict[str, list[TextEdit]], lines_of: LinesOf, uri_of: UriOf, codec: PositionCodec
) -> types.WorkspaceEdit:
    changes = {}
    for key, file_edits in edits.items():
        lines = lines_of(key)
        changes[uri_of(key)] = [
            types.TextEdit(range=to_lsp_range(e.span, lines, codec), new_text=e.new_text)
            for e in file_edits
        ]
    return types.WorkspaceEdit(changes=changes)


def to_lsp_document_symbols(
    symbols: list[DocSymbol], lines: LineIndex, codec: PositionCodec
) -> list[types.DocumentSymbol]:
    result = []
    for sym in symbols:
        rng = to_lsp_range(sym.span, lines, codec)
        selection = to_lsp_range(sym.selection, lines, codec)
        if not _inside(selection, rng):
            rng = types.Range(
                start=min(rng.start, selection.start, key=_key),
                end=max(rng.end, selection.end, key=_key),
            )
        result.append(
            types.DocumentSymbol(
                name=sym.name or "?",
                kind=_SYMBOL_KINDS.get(sym.kind, types.SymbolKind.Variable),
                range=rng,
                selection_range=selection,
                detail=sym.detail or None,
                children=to_lsp_document_symbols(sym.children, lines, codec) or None,
            )
        )
    return result


def _key(p: types.Position) -> tuple[int, int]:
    return (p.line, p.character)


def _inside(inner: types.Range, outer: types.Range) -> bool:
    return _key(outer.start) <= _key(inner.start) and _key(inner.end) <= _key(outer.end)


def to_lsp_workspace_symbols(
    symbols: list[WorkspaceSymbol], lines_of: LinesOf, uri_of: UriOf, codec: PositionCodec
) -> list[types.WorkspaceSymbol]:
    return [
        types.WorkspaceSymbol(
            name=s.name,
            kind=_SYMBOL_KINDS.get(s.kind, types.SymbolKind.Variable),
            container_name=s.container or None,
            location=to_lsp_location(s.span, lines_of, uri_of, codec),
        )
        for s in symbols
    ]


def to_lsp_semantic_tokens(
    tokens: list[SemanticToken], lines: LineIndex, codec: PositionCodec
) -> types.SemanticTokens:
    data: list[int] = []
    prev_line = prev_char = 0
    for tok in tokens:
        content = lines.line_content(tok.line)
        start = client_units(content[: tok.column], codec)
        length = client_units(content[tok.column : tok.column + tok.length], codec)
        delta_line = tok.line - prev_line
        delta_char = start - prev_char if delta_line == 0 else start
        data.extend((delta_line, delta_char, length, tok.type, tok.modifiers))
        prev_line, prev_char = tok.line, start
    return types.SemanticTokens(data=data)


def to_lsp_folding_ranges(folds: list[Fold]) -> list[types.FoldingRange]:
    kinds = {
        "comment": types.FoldingRangeKind.Comment,
        "imports": types.FoldingRangeKind.Imports,
        "region": types.FoldingRangeKind.Region,
    }
    return [
        types.FoldingRange(start_line=f.start_line, end_line=f.end_line, kind=kinds.get(f.kind))
        for f in folds
    ]


def to_lsp_signature_help(result: SignatureResult | None) -> types.SignatureHelp | None:
    if result is None:
        return None
    params = [
        types.ParameterInformation(
            label=(_utf16(result.label[:start]), _utf16(result.label[:end])),
            documentation=doc or None,
        )
        for start, end, doc in result.parameters
    ]
    signature = types.SignatureInformation(
        label=result.label,
        parameters=params,
        documentation=types.MarkupContent(
            kind=types.MarkupKind.Markdown, value=result.documentation
        )
        if result.documentation
        else None,
        active_parameter=result.active,
    )
    return types.SignatureHelp(
        signatures=[signature], active_signature=0, active_parameter=result.active
    )


def _utf16(text: str) -> int:
    """Parameter label offsets are in UTF-16 code units whatever the position encoding."""
    return len(text.encode("utf-16-le")) // 2


def to_lsp_inlay_hints(
    hints: list[Hint], lines: LineIndex, codec: PositionCodec
) -> list[types.InlayHint]:
    result = []
    for h in hints:
        parameter = h.kind == "parameter"
        result.append(
            types.InlayHint(
                position=to_lsp_position(lines, h.offset, codec),
                label=h.label,
                kind=types.InlayHintKind.Parameter if parameter else types.InlayHintKind.Type,
                padding_left=not parameter,
                padding_right=parameter,
                tooltip=h.tooltip or None,
            )
        )
    return result


def to_lsp_code_actions(
    actions: list[Action],
    snapshot: Snapshot,
    uri_of: UriOf,
    codec: PositionCodec,
    docs_url: str = "",
) -> list[types.CodeAction]:
    result = []
    for a in actions:
        result.append(
            types.CodeAction(
                title=a.title,
                kind=types.CodeActionKind.QuickFix,
                diagnostics=to_lsp_diagnostics(
                    snapshot.lines_of, a.diagnostics, uri_of, codec, docs_url
                ),
                is_preferred=a.preferred or None,
                edit=to_lsp_workspace_edit(a.edits, snapshot.lines_of, uri_of, codec),
            )
        )
    return result


def line_edits(old: str, new: str) -> list[tuple[int, int, str]]:
    """Edits ``(first_line, end_line, replacement)`` (0-based, end exclusive) that turn
    ``old`` into ``new``, one per run of changed lines.

    Lines end where the client's do (``LineIndex``), not where ``str.splitlines``
    would also break (a form feed in a comment is no line break)."""
    a = [re.sub(r"\r\n|\r", "\n", line) for line in _lines(old)]
    b = _lines(new)
    edits = []
    matcher = difflib.SequenceMatcher(None, a, b, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag != "equal":
            edits.append((i1, i2, "".join(b[j1:j2])))
    return edits


def _lines(text: str) -> list[str]:
    """The lines of ``text`` with their line breaks (no empty last line)."""
    lines = LineIndex(text).lines()
    return lines[:-1] if not lines[-1] else lines


def to_lsp_format_edits(old: str, new: str, lines: LineIndex) -> list[types.TextEdit]:
    """Line-level edits; line numbers only, so no unit conversion is needed."""
    edits = []
    for first, end, text in line_edits(old, new):
        start = types.Position(line=first, character=0)
        if end >= len(lines) and not lines.text.endswith(("\n", "\r")):
            stop = types.Position(line=len(lines), character=0)
        else:
            stop = types.Position(line=end, character=0)
        edits.append(types.TextEdit(range=types.Range(start=start, end=stop), new_text=text))
    return edits


def default_uri_of(key: str) -> str:
    return key_to_uri(key)
