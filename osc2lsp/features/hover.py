"""Hover: what a name declares, what an expression is worth, what a code means, what a
map holds (on the string of a ``map_file``: its roads, lanes and junctions)."""

from __future__ import annotations

import re
from dataclasses import dataclass

from osc2check import codes, rules
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.semantics.visibility import node_path
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.maps import load_map, scenario_folder
from osc2lsp.features import describe
from osc2lsp.features.values import Quantity, evaluate, value_of
from osc2lsp.features.values import describe as describe_value
from osc2lsp.snapshot import Snapshot

_CODE_WORD = re.compile(r"[A-Za-z][\w-]*")
_EXPRESSIONS = (
    ast.IntLiteral,
    ast.FloatLiteral,
    ast.PhysicalLiteral,
    ast.StringLiteral,
    ast.BoolLiteral,
    ast.NameRef,
    ast.EnumRef,
    ast.MemberAccess,
    ast.Call,
    ast.Index,
    ast.Unary,
    ast.Binary,
    ast.Ternary,
    ast.ListLiteral,
    ast.RangeLiteral,
)


@dataclass(frozen=True, slots=True)
class HoverResult:
    markdown: str
    span: Span | None = None


def hover(snapshot: Snapshot, offset: int) -> HoverResult | None:
    """The hover text at ``offset`` of the snapshot's text, or None."""
    in_comment = _code_in_comment(snapshot, offset)
    if in_comment is not None:
        return in_comment
    path = node_path(snapshot.ast, offset)
    literal = next((n for n in reversed(path) if isinstance(n, ast.PhysicalLiteral)), None)
    if literal is not None:
        return _literal(snapshot, literal)
    found = _map_file(snapshot, path)
    if found is not None:
        return found
    entry = snapshot.name_at(offset)
    if entry is not None:
        return HoverResult(symbol_markdown(snapshot, entry.symbol), entry.name.span)
    expr = next((n for n in reversed(path) if isinstance(n, _EXPRESSIONS)), None)
    if expr is not None:
        return _expression(snapshot, expr)
    return None


def symbol_markdown(snapshot: Snapshot, sym: Symbol) -> str:
    """Signature, kind and owner, value, documentation and origin of a symbol."""
    parts = [f"```osc\n{describe.signature(snapshot, sym)}\n```"]
    facts = [sym.kind.value]
    owner = describe.owner_text(sym)
    if owner:
        facts[0] += f" of {owner}"
    if sym.type is not None and sym.kind in (
        SymbolKind.FIELD,
        SymbolKind.VARIABLE,
        SymbolKind.GLOBAL,
        SymbolKind.ARGUMENT,
        SymbolKind.IMPLICIT,
    ):
        facts.append(f"type `{describe.type_text(sym.type)}`")
    if sym.namespace:
        facts.append(f"namespace `{sym.namespace}`")
    if sym.library:
        facts.append("standard library" if not sym.toolkit else "toolkit library")
    parts.append(" · ".join(facts))
    value = value_of(snapshot.model, sym)
    if value is not None and value.physical:
        parts.append(f"value: {describe_value(value)}")
    if sym.kind is SymbolKind.UNIT and sym.dimension is not None:
        one = Quantity(sym.factor + sym.offset, sym.dimension)
        parts.append(f"1 {sym.name} = {describe_value(one)}")
    if sym.kind in (
        SymbolKind.SCENARIO,
        SymbolKind.ACTION,
        SymbolKind.MODIFIER,
        SymbolKind.METHOD,
        SymbolKind.EVENT,
    ):
        params = describe.parameters_of(snapshot.model, sym)
        if params:
            parts.append(
                "parameters: "
                + ", ".join(f"`{describe.parameter_text(snapshot, p)}`" for p in params)
            )
    doc = describe.markdown_doc(sym)
    if doc:
        parts.append(doc)
    return "\n\n".join(parts)


def _literal(snapshot: Snapshot, literal: ast.PhysicalLiteral) -> HoverResult:
    t = snapshot.model.expr_types.get(literal)
    q = evaluate(snapshot.model, literal)
    parts = [f"```osc\n{literal.number_text}{literal.unit.text}\n```"]
    if t is not None:
        parts.append(f"type `{describe.type_text(t)}`")
    if q is not None:
        parts.append(f"value: {describe_value(q)}")
    unit = snapshot.model.references.get(literal.unit)
    if unit is not None and unit.doc:
        parts.append(f"`{unit.name}`: {unit.doc.strip()}")
    return HoverResult("\n\n".join(parts), literal.span)


def _expression(snapshot: Snapshot, expr: ast.Node) -> HoverResult | None:
    t = snapshot.model.expr_types.get(expr)
    q = evaluate(snapshot.model, expr)
    if t is None and q is None:
        return None
    text = describe.source_text(snapshot, expr)
    if len(text) > 80 or "\n" in text:
        text = text[:77].split("\n")[0] + "..."
    parts = [f"```osc\n{text}\n```"]
    if t is not None:
        parts.append(f"type `{describe.type_text(t)}`")
    if q is not None and q.physical:
        parts.append(f"value: {describe_value(q)}")
    return HoverResult("\n\n".join(parts), expr.span)


def _map_file(snapshot: Snapshot, path: list[ast.Node]) -> HoverResult | None:
    """On the string a ``map_file`` is given (``keep(m.map_file == "x.xodr")``,
    ``map.set_map_file("x.xodr")``): the map's summary, or why it cannot be read."""
    if not path or not isinstance(path[-1], ast.StringLiteral):
        return None
    string = path[-1]
    parent = next(
        (n for n in reversed(path[:-1]) if isinstance(n, (ast.Binary, ast.Invocation))), None
    )
    if isinstance(parent, ast.Invocation):
        if parent.name.text != "set_map_file":
            return None
    elif isinstance(parent, ast.Binary):
        other = parent.left if parent.right is string else parent.right
        name = other.member.text if isinstance(other, ast.MemberAccess) else None
        if parent.op != "==" or name != "map_file":
            return None
    else:
        return None
    try:
        text = load_map(string.value, scenario_folder(snapshot.key)).summary().text()
    except (MapError, UnknownMapError) as error:
        text = f"**{string.value}**: cannot be read: {error}"
    return HoverResult(text, string.span)


def _code_in_comment(snapshot: Snapshot, offset: int) -> HoverResult | None:
    for comment in snapshot.parse.comments:
        if comment.offset <= offset <= comment.offset + len(comment.text):
            rel = offset - comment.offset
            for match in _CODE_WORD.finditer(comment.text):
                if match.start() <= rel <= match.end():
                    code = codes.lookup(match.group())
                    if code is None:
                        return None
                    return HoverResult(code_markdown(code))
            return None
    return None


def code_markdown(code: codes.Code) -> str:
    try:
        return rules.page_text(code)
    except (FileNotFoundError, KeyError, OSError):
        return f"**{code.code} {code.slug}** — {code.summary}"
