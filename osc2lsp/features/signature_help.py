"""Signature help inside the argument list of an invocation or a call."""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.semantics.builtins import EVENT_FUNCTIONS
from osc2check.semantics.calls import next_parameter, written_name
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2lsp.features import describe
from osc2lsp.features.completion import enclosing_call
from osc2lsp.features.context import Focus, cursor_at, focus
from osc2lsp.snapshot import Snapshot


@dataclass(frozen=True, slots=True)
class SignatureResult:
    label: str
    parameters: list[tuple[int, int, str]]  # (start, end) in label, documentation
    active: int | None
    documentation: str = ""


def signature_help(snapshot: Snapshot | None, text: str, offset: int) -> SignatureResult | None:
    cursor = cursor_at(text, offset)
    if cursor.in_comment or cursor.in_string:
        return None
    f = focus(snapshot, text, offset, cursor)
    call = enclosing_call(f)
    if call is None:
        return _builtin(f)
    node, callee = call
    params = describe.parameters_of(f.model, callee)
    snap = snapshot
    texts = [describe.parameter_text(snap, p) if snap is not None else p.name for p in params]
    name = callee.qualified_name if callee.kind is not SymbolKind.METHOD else callee.name
    label = f"{name}("
    spans = []
    for i, t in enumerate(texts):
        if i:
            label += ", "
        spans.append((len(label), len(label) + len(t), describe.markdown_doc(params[i])))
        label += t
    label += ")"
    return SignatureResult(label, spans, _active(f, node, params), describe.markdown_doc(callee))


def _active(f: Focus, node: ast.Invocation | ast.Call, params: list[Symbol]) -> int | None:
    path = f.path
    arg = next((n for n in path if any(n is a for a in node.arguments)), None)
    if arg is None:
        index = f.cursor.argument_index()
        args = list(node.arguments)
        if index is not None and index < len(args):
            arg = args[index]
        elif index is not None:  # an argument being typed after the last one analysed
            following = next_parameter(args)
            return following if following is not None and following < len(params) else None
        else:
            return 0 if params else None
    binding = f.model.binding(node)
    name = binding.parameter_of(arg) if binding is not None else None
    if name is None:  # not bound: a misspelt name, or text the analysis has not seen
        name = written_name(arg)
    names = [p.name for p in params]
    return names.index(name) if name in names else None


def _builtin(f: Focus) -> SignatureResult | None:
    for node in reversed(f.path):
        if isinstance(node, ast.Call) and isinstance(node.callee, ast.NameRef):
            name = node.callee.name.name.text
            builtin = EVENT_FUNCTIONS.get(name)
            if builtin is not None:
                label = builtin.signature
                spans = []
                start = label.index("(") + 1
                for param in builtin.parameters:
                    spans.append((start, start + len(param.text), ""))
                    start += len(param.text) + 2
                doc = builtin.doc[0].upper() + builtin.doc[1:] + "."
                return SignatureResult(label, spans, 0, doc)
    return None
