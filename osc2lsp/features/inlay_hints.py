"""Inlay hints (opt-in): folded values of physical expressions, parameter names.

* after an initialiser or argument that is not a plain literal and folds to a
  physical constant: its value in the unit it was written in
  (``v_hero + 12.42mph`` → ``≈ 55.0 kph``);
* before a positional argument of an invocation or call: the parameter the
  checker bound it to (``lane(lane: 1, at: start)``).
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.semantics.bindings import argument_values
from osc2check.semantics.visibility import extent
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2lsp.features.values import evaluate, short
from osc2lsp.snapshot import Snapshot

_LITERALS = (
    ast.PhysicalLiteral,
    ast.IntLiteral,
    ast.FloatLiteral,
    ast.StringLiteral,
    ast.BoolLiteral,
    ast.Missing,
)


@dataclass(frozen=True, slots=True)
class Hint:
    offset: int
    label: str
    kind: str  # "value" | "parameter"
    tooltip: str = ""


def inlay_hints(
    snapshot: Snapshot, start: int, end: int, values: bool = True, parameter_names: bool = True
) -> list[Hint]:
    model = snapshot.model
    hints: list[Hint] = []
    for decl in snapshot.ast.declarations:
        if decl.span.end < start or decl.span.start > end:
            continue
        for node in walk(decl):
            if not start <= node.span.start <= end:
                continue
            if values and isinstance(node, ast.FieldDecl) and node.default is not None:
                _value_hint(snapshot, node.default, hints)
            if isinstance(node, (ast.Invocation, ast.Call)):
                binding = model.binding(node)
                if parameter_names and binding is not None:
                    for bound in binding.arguments:
                        if bound.positional and not (
                            isinstance(bound.value, ast.NameRef)
                            and bound.value.name.name.text == bound.name
                        ):
                            hints.append(Hint(bound.span.start, f"{bound.name}:", "parameter"))
                if values:
                    for value in argument_values(node.arguments):
                        _value_hint(snapshot, value, hints)
    hints.sort(key=lambda h: h.offset)
    return hints


def _value_hint(snapshot: Snapshot, expr: ast.Node, hints: list[Hint]) -> None:
    if isinstance(expr, _LITERALS) or (
        isinstance(expr, ast.Unary) and isinstance(expr.operand, _LITERALS)
    ):
        return
    q = evaluate(snapshot.model, expr)
    if q is None or not q.physical:
        return
    text = short(q)
    if not text.startswith("≈"):
        text = f"= {text}"
    hints.append(Hint(extent(expr), text, "value"))
