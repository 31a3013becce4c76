"""Rename a declaration and every use of it, across the open documents' programs.

Renaming is refused for names of the bundled library (``Symbol.library``),
for implicit names (``it``, ``actor``, event bindings of the language), for
a new name that is not an identifier, is a reserved keyword or an implicit
name, and when the new name is already declared in the same scope.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from osc2check.diagnostics import TextEdit
from osc2check.semantics.symbols import IMPLICIT_NAMES, Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax.expected import keywords, soft_keywords
from osc2lsp.features.navigation import declaration_span, references_of, symbol_at
from osc2lsp.snapshot import Snapshot

_IDENTIFIER = re.compile(r"[^\W\d]\w*")


class RenameError(Exception):
    """Why a rename cannot be done (shown to the user)."""


def prepare_rename(snapshot: Snapshot, offset: int) -> tuple[Span, str]:
    """The range to rename and its current text; raises ``RenameError``."""
    entry = snapshot.name_at(offset)
    if entry is None:
        raise RenameError("no symbol to rename here")
    _check_symbol(entry.symbol)
    return entry.name.span, entry.name.text


def rename(
    snapshot: Snapshot, offset: int, new_name: str, others: Iterable[Snapshot] = ()
) -> dict[str, list[TextEdit]]:
    """Edits by file key that rename the symbol at ``offset``; raises ``RenameError``."""
    sym = symbol_at(snapshot, offset)
    if sym is None:
        raise RenameError("no symbol to rename here")
    _check_symbol(sym)
    _check_name(new_name)
    if new_name == sym.name:
        return {}
    _check_collision(snapshot, sym, new_name)
    edits: dict[str, list[TextEdit]] = {}
    for span in references_of(sym, [snapshot, *others], include_declaration=True):
        edits.setdefault(span.uri, []).append(TextEdit(span, new_name))
    return edits


def _check_symbol(sym: Symbol) -> None:
    if sym.library:
        raise RenameError(f"`{sym.name}` is declared by the standard library and cannot be renamed")
    if sym.kind in (SymbolKind.IMPLICIT, SymbolKind.PRIMITIVE) or declaration_span(sym) is None:
        raise RenameError(f"`{sym.name}` is not declared in a file that can be edited")


def _check_name(name: str) -> None:
    if not _IDENTIFIER.fullmatch(name):
        raise RenameError(f"`{name}` is not a valid name")
    reserved = {text for term, text in keywords().items() if term not in soft_keywords()}
    if name in reserved:
        raise RenameError(f"`{name}` is a keyword")
    if name in IMPLICIT_NAMES:
        raise RenameError(f"`{name}` is a name the language gives; choose another")


def _check_collision(snapshot: Snapshot, sym: Symbol, new_name: str) -> None:
    model = snapshot.model
    if sym.owner is not None and sym.kind in (
        SymbolKind.FIELD,
        SymbolKind.VARIABLE,
        SymbolKind.EVENT,
        SymbolKind.METHOD,
    ):
        clash = [
            s
            for s in model.member(sym.owner, new_name)
            if s.kind is not SymbolKind.METHOD or sym.kind is not SymbolKind.METHOD
        ]
        if clash:
            raise RenameError(f"`{sym.owner.name}` already has a member `{new_name}`")
    elif sym.kind is SymbolKind.ENUM_MEMBER and sym.owner is not None:
        if any(m.name == new_name for m in model.enum_values(sym.owner)):
            raise RenameError(f"enum `{sym.owner.name}` already has a member `{new_name}`")
    elif sym.kind is SymbolKind.UNIT:
        if model.unit(new_name) is not None:
            raise RenameError(f"a unit `{new_name}` already exists")
    elif sym.owner is None and sym.kind is not SymbolKind.LABEL and sym.actor is None:
        ns = model.namespace(sym.namespace)
        if ns is not None and new_name in ns.symbols:
            raise RenameError(f"`{new_name}` is already declared in this namespace")
