"""Semantic tokens: what each name is, from the lexer's tokens and the resolved names.

Keywords, strings, numbers and comments are left to the editor's TextMate
grammar; this adds what only the analysis knows: which names are actors,
actions, modifiers, parameters, events, enum members, units, labels, and
which come from the standard library.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax.lexer import Token, tokenize
from osc2lsp.features.legend import TOKEN_MODIFIERS, TOKEN_TYPES
from osc2lsp.snapshot import NameEntry, Snapshot
from osc2lsp.text import LineIndex

__all__ = ["TOKEN_MODIFIERS", "TOKEN_TYPES", "SemanticToken", "semantic_tokens"]

_KINDS = {
    SymbolKind.PRIMITIVE: "type",
    SymbolKind.PHYSICAL_TYPE: "type",
    SymbolKind.UNIT: "unit",
    SymbolKind.ENUM: "enum",
    SymbolKind.ENUM_MEMBER: "enumMember",
    SymbolKind.STRUCT: "struct",
    SymbolKind.ACTOR: "class",
    SymbolKind.SCENARIO: "function",
    SymbolKind.ACTION: "function",
    SymbolKind.MODIFIER: "decorator",
    SymbolKind.FIELD: "property",
    SymbolKind.VARIABLE: "variable",
    SymbolKind.EVENT: "event",
    SymbolKind.METHOD: "method",
    SymbolKind.ARGUMENT: "parameter",
    SymbolKind.GLOBAL: "variable",
    SymbolKind.LABEL: "label",
    SymbolKind.IMPLICIT: "variable",
}
_TYPE_INDEX = {name: i for i, name in enumerate(TOKEN_TYPES)}


@dataclass(frozen=True, slots=True)
class SemanticToken:
    line: int  # 0-based
    column: int  # 0-based, code points
    length: int  # code points
    type: int  # index into TOKEN_TYPES
    modifiers: int  # bit set over TOKEN_MODIFIERS


def _modifiers(sym: Symbol, declaration: bool) -> int:
    bits = 0
    if declaration:
        bits |= 1
    if sym.kind in (SymbolKind.GLOBAL, SymbolKind.ENUM_MEMBER, SymbolKind.UNIT):
        bits |= 2
    if sym.library:
        bits |= 4
    return bits


def semantic_tokens(
    snapshot: Snapshot, start: int = 0, end: int | None = None
) -> list[SemanticToken]:
    """Tokens of the document (or of the offsets ``start``..``end``), in order."""
    text = snapshot.text
    end = len(text) if end is None else end
    by_start = {e.start: e for e in snapshot.names}
    lines = snapshot.lines
    out: list[SemanticToken] = []
    for tok in tokenize(text).tokens:
        if tok.start_pos < start:
            continue
        if tok.start_pos >= end:
            break
        if tok.type == "PHYSICAL":
            out.extend(_physical(tok, by_start, lines))
            continue
        entry = by_start.get(tok.start_pos)
        if entry is None or entry.end != tok.end_pos:
            continue
        sym = entry.symbol
        kind = _KINDS.get(sym.kind)
        if kind is None:
            continue
        declaration = (
            sym.name_span is not None
            and sym.name_span.start == tok.start_pos
            and sym.name_span.uri == snapshot.key
        )
        line, column = lines.position(tok.start_pos)
        out.append(
            SemanticToken(
                line,
                column,
                tok.end_pos - tok.start_pos,
                _TYPE_INDEX[kind],
                _modifiers(sym, declaration),
            )
        )
    return out


def _physical(tok: Token, by_start: dict[int, NameEntry], lines: LineIndex) -> list[SemanticToken]:
    value = tok.value
    number = len(value)
    for i, ch in enumerate(value):
        if not (ch.isdigit() or ch in ".eE+-"):
            number = i
            break
        if ch in "eE" and not (
            i + 1 < len(value) and (value[i + 1].isdigit() or value[i + 1] in "+-")
        ):
            number = i
            break
    line, column = lines.position(tok.start_pos)
    out = [SemanticToken(line, column, number, _TYPE_INDEX["number"], 0)]
    unit_start = tok.start_pos + number
    entry = by_start.get(unit_start)
    modifiers = _modifiers(entry.symbol, False) if entry is not None else 0
    out.append(
        SemanticToken(line, column + number, len(value) - number, _TYPE_INDEX["unit"], modifiers)
    )
    return out
