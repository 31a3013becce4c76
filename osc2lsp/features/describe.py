"""How declarations read in hovers, completions and signatures."""

from __future__ import annotations

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.semantics.types import Kind, Type
from osc2check.source import strip_comment
from osc2check.syntax import ast
from osc2lsp.snapshot import Snapshot

KIND_WORDS = {
    SymbolKind.FIELD: "parameter",
    SymbolKind.VARIABLE: "variable",
    SymbolKind.ARGUMENT: "argument",
    SymbolKind.GLOBAL: "global parameter",
}


def source_text(snapshot: Snapshot, node: ast.Node | None) -> str:
    """The source text of ``node`` (from whichever file it is in)."""
    if node is None:
        return ""
    text = snapshot.text_of(node.span.uri)
    if text is None:
        return ""
    return text[node.span.start : node.span.end]


def first_line(snapshot: Snapshot, node: ast.Node | None) -> str:
    """The first source line of ``node``, without a trailing `:`."""
    if node is None:
        return ""
    text = snapshot.text_of(node.span.uri)
    if text is None:
        return ""
    end = text.find("\n", node.span.start)
    line = text[node.span.start : end if end != -1 else len(text)].rstrip()
    if "#" in line:
        line = strip_comment(line).rstrip()
    return line.rstrip(":").rstrip() if line.endswith(":") else line


def type_text(t: Type | None) -> str:
    if t is None or t.kind is Kind.UNKNOWN:
        return "?"
    return str(t)


def parameter_text(snapshot: Snapshot, param: Symbol) -> str:
    """``side: side_left_right`` or ``lane: uint = 1``."""
    text = f"{param.name}: {type_text(param.type)}"
    if param.default is not None:
        text += f" = {source_text(snapshot, param.default)}"
    return text


def signature(snapshot: Snapshot, sym: Symbol) -> str:
    """A one-line declaration of ``sym`` in OSC2 syntax."""
    kind = sym.kind
    decl = sym.decl
    if kind in (SymbolKind.FIELD, SymbolKind.VARIABLE, SymbolKind.GLOBAL):
        prefix = (
            "var "
            if kind is SymbolKind.VARIABLE
            else "global "
            if kind is SymbolKind.GLOBAL
            else ""
        )
        text = f"{prefix}{sym.name}: {type_text(sym.type)}"
        if sym.default is not None:
            text += f" = {source_text(snapshot, sym.default)}"
        return text
    if kind is SymbolKind.ARGUMENT:
        return parameter_text(snapshot, sym)
    if kind is SymbolKind.ENUM_MEMBER:
        owner = sym.owner.name if sym.owner is not None else "?"
        return f"{owner}!{sym.name} = {sym.value}"
    if kind is SymbolKind.EVENT:
        params = ", ".join(parameter_text(snapshot, p) for p in sym.parameters)
        text = f"event {sym.name}" + (f"({params})" if params else "")
        if sym.extra.get("implicit"):
            text += "  # emitted without a declaration"
        return text
    if kind is SymbolKind.METHOD:
        params = ", ".join(parameter_text(snapshot, p) for p in sym.parameters)
        ret = (
            f" -> {type_text(sym.type)}"
            if sym.type is not None and sym.type.kind is not Kind.NONE
            else ""
        )
        return f"def {sym.name}({params}){ret}"
    if kind is SymbolKind.LABEL:
        return f"label {sym.name}"
    if kind is SymbolKind.IMPLICIT:
        return f"{sym.name}: {type_text(sym.type)}"
    if kind is SymbolKind.PRIMITIVE:
        return f"type {sym.name}"
    if decl is not None and sym.uri:
        line = first_line(snapshot, decl)
        if line:
            return line
    return f"{kind.value} {sym.qualified_name}"


def owner_text(sym: Symbol) -> str:
    owner = sym.owner
    if owner is None:
        return ""
    return f"{owner.kind.value} `{owner.qualified_name}`"


def parameters_of(model: Model, sym: Symbol) -> list[Symbol]:
    """What an invocation of ``sym`` takes: fields of a behaviour or modifier,
    arguments of a method or event."""
    if sym.kind in (SymbolKind.METHOD, SymbolKind.EVENT):
        return list(sym.parameters)
    if sym.kind in (SymbolKind.SCENARIO, SymbolKind.ACTION, SymbolKind.MODIFIER):
        return model.parameters(sym)
    return []


def markdown_doc(sym: Symbol) -> str:
    return sym.doc.strip() if sym.doc else ""
