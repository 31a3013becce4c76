"""Document outline and workspace symbols.

The outline lists declarations with their members: fields, variables, events,
methods, enum members, and the ``do`` tree as its compositions and labelled
phases. It is built from the recovered AST, so a broken statement removes
only itself from the outline.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from osc2check.semantics.stdlib import standard_library
from osc2check.semantics.symbols import SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2lsp.snapshot import Snapshot

_DECL_KINDS = {
    ast.ScenarioDecl: "scenario",
    ast.ActorDecl: "actor",
    ast.StructDecl: "struct",
    ast.ActionDecl: "action",
    ast.ModifierDecl: "modifier",
}
_SYMBOL_KINDS = {
    SymbolKind.SCENARIO: "scenario",
    SymbolKind.ACTOR: "actor",
    SymbolKind.STRUCT: "struct",
    SymbolKind.ACTION: "action",
    SymbolKind.MODIFIER: "modifier",
    SymbolKind.ENUM: "enum",
    SymbolKind.PHYSICAL_TYPE: "type",
    SymbolKind.UNIT: "unit",
    SymbolKind.GLOBAL: "global",
}


@dataclass
class DocSymbol:
    name: str
    kind: str  # scenario actor struct action modifier enum enum_member type unit field
    #            variable event method label do namespace extend global
    span: Span  # the whole declaration
    selection: Span  # its name
    detail: str = ""
    children: list[DocSymbol] = field(default_factory=list)


@dataclass(frozen=True, slots=True)
class WorkspaceSymbol:
    name: str
    kind: str
    container: str
    span: Span


def document_symbols(snapshot: Snapshot) -> list[DocSymbol]:
    result: list[DocSymbol] = []
    for decl in snapshot.ast.declarations:
        sym = _declaration(decl)
        if sym is not None:
            result.append(sym)
    return result


def _declaration(decl: ast.Node) -> DocSymbol | None:
    match decl:
        case ast.StructuredDecl():
            name = decl.name
            if name.name.missing:
                return None
            kind = _DECL_KINDS.get(type(decl), "struct")
            detail = f"inherits {decl.inherits.target}" if decl.inherits else ""
            if isinstance(decl, ast.ModifierDecl) and decl.of is not None:
                detail = f"of {decl.of}"
            sym = DocSymbol(str(name), kind, decl.span, name.span, detail)
            sym.children = _members(decl.members)
            return sym
        case ast.ExtendDecl():
            sym = DocSymbol(f"extend {decl.target}", "extend", decl.span, decl.target.span)
            sym.children = _members(decl.members)
            return sym
        case ast.EnumDecl() | ast.EnumExtension():
            enum_name = decl.name if isinstance(decl, ast.EnumDecl) else decl.target.name
            label = enum_name.text if isinstance(decl, ast.EnumDecl) else f"extend {decl.target}"
            sym = DocSymbol(label, "enum", decl.span, enum_name.span)
            sym.children = [
                DocSymbol(m.name.text, "enum_member", m.span, m.name.span)
                for m in decl.members
                if m.name.text
            ]
            return sym
        case ast.PhysicalTypeDecl():
            return DocSymbol(decl.name.text, "type", decl.span, decl.name.span)
        case ast.UnitDecl():
            return DocSymbol(decl.name.text, "unit", decl.span, decl.name.span, f"of {decl.type}")
        case ast.GlobalDecl():
            names = [n for n in decl.field.names if n.text]
            if not names:
                return None
            return DocSymbol(", ".join(n.text for n in names), "global", decl.span, names[0].span)
        case ast.NamespaceDecl():
            if not decl.name.text:
                return None
            return DocSymbol(decl.name.text, "namespace", decl.span, decl.name.span)
    return None


def _members(members: Iterable[ast.Node]) -> list[DocSymbol]:
    result: list[DocSymbol] = []
    for member in members:
        match member:
            case ast.FieldDecl():
                kind = "variable" if member.is_var else "field"
                detail = str(member.type.name) if isinstance(member.type, ast.NamedType) else ""
                for name in member.names:
                    if name.text:
                        result.append(DocSymbol(name.text, kind, member.span, name.span, detail))
            case ast.EventDecl():
                if member.name.text:
                    result.append(
                        DocSymbol(member.name.text, "event", member.span, member.name.span)
                    )
            case ast.MethodDecl():
                if member.name.text:
                    result.append(
                        DocSymbol(member.name.text, "method", member.span, member.name.span)
                    )
            case ast.DoDirective():
                do = _do_member(member.member, prefix="do ")
                if do is not None:
                    result.append(do)
    return result


def _do_member(member: ast.DoMember, prefix: str = "") -> DocSymbol | None:
    body = member.body
    named = member.label if member.label is not None and member.label.text else None
    label = named.text if named is not None else None
    selection = named.span if named is not None else member.span
    if isinstance(body, ast.Composition):
        name = f"{label}: {body.op}" if label else f"{prefix}{body.op}"
        sym = DocSymbol(name, "label" if label else "do", member.span, selection)
        for inner in body.members:
            child = _do_member(inner)
            if child is not None:
                sym.children.append(child)
        return sym
    if label:
        detail = ""
        if isinstance(body, ast.Invocation):
            detail = body.name.text
        return DocSymbol(label, "label", member.span, selection, detail)
    return None


# ---- workspace symbols ----------------------------------------------------------


def _flatten(symbols: list[DocSymbol], container: str = "") -> Iterable[WorkspaceSymbol]:
    for sym in symbols:
        if sym.kind != "do":
            yield WorkspaceSymbol(sym.name, sym.kind, container, sym.selection)
        yield from _flatten(sym.children, sym.name if sym.kind != "do" else container)


def matches(query: str, name: str) -> bool:
    """Case-insensitive subsequence match (``cl`` finds ``change_lane``)."""
    if not query:
        return True
    q, n = query.lower(), name.lower()
    i = 0
    for ch in n:
        if i < len(q) and ch == q[i]:
            i += 1
    return i == len(q)


def workspace_symbols(
    snapshots: Iterable[Snapshot], query: str, limit: int = 500, library: bool = True
) -> list[WorkspaceSymbol]:
    """Declarations of the open documents (and, for a non-empty query, of the library)."""
    found: dict[tuple[str, int], WorkspaceSymbol] = {}
    for snap in snapshots:
        for sym in _flatten(document_symbols(snap)):
            if matches(query, sym.name):
                found.setdefault((sym.span.uri, sym.span.start), sym)
    if library and query:
        for declared in standard_library().model.symbols:
            kind = _SYMBOL_KINDS.get(declared.kind)
            span = declared.name_span
            if kind is None or span is None or not matches(query, declared.name):
                continue
            container = declared.actor.name if declared.actor is not None else declared.namespace
            found.setdefault(
                (span.uri, span.start), WorkspaceSymbol(declared.name, kind, container, span)
            )
    ranked = sorted(
        found.values(),
        key=lambda s: (not s.name.lower().startswith(query.lower()), len(s.name), s.name),
    )
    return ranked[:limit]
