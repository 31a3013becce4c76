"""Go to definition, type definition, references and document highlights.

A symbol is identified across analyses by ``symbol_key`` (its file and the
offset of its name), because every program builds its own ``Symbol`` objects:
a file imported by two open documents is resolved once for each.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from osc2check.resources import stdlib_dir
from osc2check.semantics.stdlib import LIBRARY_FILES, STANDARD_FILE_NAMES, STANDARD_MODULES
from osc2check.semantics.symbols import Symbol
from osc2check.semantics.types import Kind, Type
from osc2check.source import Span
from osc2check.syntax import ast
from osc2lsp.features.lookup import path_at
from osc2lsp.snapshot import Snapshot, symbol_key

_EXPRESSIONS = (
    ast.NameRef,
    ast.MemberAccess,
    ast.Call,
    ast.Index,
    ast.Binary,
    ast.Unary,
    ast.PhysicalLiteral,
    ast.EnumRef,
    ast.Ternary,
    ast.ListLiteral,
    ast.RangeLiteral,
)


def symbol_at(snapshot: Snapshot, offset: int) -> Symbol | None:
    entry = snapshot.name_at(offset)
    return entry.symbol if entry is not None else None


def declaration_span(sym: Symbol) -> Span | None:
    span = sym.name_span
    if span is None or not span.uri or span.uri.startswith("<"):
        return None
    return span


def definition(snapshot: Snapshot, offset: int) -> list[Span]:
    """Where the name at ``offset`` is declared (or the file an import names)."""
    target = _import_target(snapshot, offset)
    if target is not None:
        return [target]
    sym = symbol_at(snapshot, offset)
    if sym is None:
        return []
    span = declaration_span(sym)
    return [span] if span is not None else []


def type_definition(snapshot: Snapshot, offset: int) -> list[Span]:
    """Where the type of the name or expression at ``offset`` is declared."""
    sym = symbol_at(snapshot, offset)
    t: Type | None = None
    if sym is not None:
        if sym.kind.is_type:
            t = sym.type
        elif sym.kind.value == "enum member":
            t = sym.owner.type if sym.owner is not None else None
        else:
            t = sym.type
    if t is None:
        path = path_at(snapshot, offset)
        expr = next((n for n in reversed(path) if isinstance(n, _EXPRESSIONS)), None)
        t = snapshot.model.expr_types.get(expr) if expr is not None else None
    while t is not None and t.kind in (Kind.LIST, Kind.RANGE) and t.element is not None:
        t = t.element
    if t is None or t.symbol is None:
        return []
    span = declaration_span(t.symbol)
    return [span] if span is not None else []


def references(
    snapshot: Snapshot,
    offset: int,
    include_declaration: bool = True,
    others: Iterable[Snapshot] = (),
) -> list[Span]:
    """Every use of the symbol at ``offset`` in the document's program and in the
    programs of ``others`` (the other open documents)."""
    sym = symbol_at(snapshot, offset)
    if sym is None:
        return []
    return references_of(sym, [snapshot, *others], include_declaration)


def references_of(
    sym: Symbol, snapshots: Iterable[Snapshot], include_declaration: bool = True
) -> list[Span]:
    key = symbol_key(sym)
    decl = declaration_span(sym)
    found: dict[tuple[str, int], Span] = {}
    for snap in snapshots:
        for file_key in snap.files():
            for entry in snap.names_in(file_key):
                if entry.symbol is sym or (
                    entry.symbol.name == sym.name and symbol_key(entry.symbol) == key
                ):
                    span = entry.name.span
                    found.setdefault((span.uri, span.start), span)
    if decl is not None:
        if include_declaration:
            found.setdefault((decl.uri, decl.start), decl)
        else:
            found.pop((decl.uri, decl.start), None)
    return sorted(found.values(), key=lambda s: (s.uri, s.start))


def highlights(snapshot: Snapshot, offset: int) -> list[Span]:
    """The uses of the symbol at ``offset`` in this document only."""
    sym = symbol_at(snapshot, offset)
    if sym is None:
        return []
    key = symbol_key(sym)
    return [e.name.span for e in snapshot.names if e.symbol is sym or symbol_key(e.symbol) == key]


def _import_target(snapshot: Snapshot, offset: int) -> Span | None:
    for decl in snapshot.ast.declarations:
        if not isinstance(decl, ast.ImportDecl):
            continue
        span = decl.target_span
        if not span.start <= offset <= span.end:
            continue
        path = import_path(snapshot.key, decl)
        if path is None or not path.is_file():
            return None
        return Span(str(path), 1, 1, 1, 1, 0, 0)
    return None


def import_path(importer: str, decl: ast.ImportDecl) -> Path | None:
    """The file an import names, as the checker resolves it (library modules too)."""
    target = decl.target
    if decl.kind == "module":
        if target in STANDARD_MODULES:
            return stdlib_dir() / LIBRARY_FILES[1]
        relative = target.replace(".", "/") + ".osc"
    else:
        relative = target[len("file://") :] if target.startswith("file://") else target
    base = (
        Path(importer).parent
        if importer and not importer.startswith(("<", "untitled:"))
        else Path.cwd()
    )
    path = Path(relative)
    path = path if path.is_absolute() else base / path
    if decl.kind == "file" and not path.is_file() and Path(target).name in STANDARD_FILE_NAMES:
        return stdlib_dir() / LIBRARY_FILES[1]
    return path
