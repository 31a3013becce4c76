"""Generic traversal of AST nodes, and the ``--dump-ast`` text view."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import fields

from osc2check.syntax import ast

_FIELD_NAMES: dict[type, tuple[str, ...]] = {}


def _field_names(cls: type) -> tuple[str, ...]:
    names = _FIELD_NAMES.get(cls)
    if names is None:
        names = _FIELD_NAMES[cls] = tuple(f.name for f in fields(cls) if f.name != "span")
    return names


def children(node: ast.Node) -> Iterator[ast.Node]:
    """The direct child nodes of ``node``, in source order."""
    for name in _field_names(type(node)):
        value = getattr(node, name)
        if isinstance(value, ast.Node):
            yield value
        elif isinstance(value, tuple):
            for item in value:
                if isinstance(item, ast.Node):
                    yield item
                elif isinstance(item, tuple):
                    yield from (x for x in item if isinstance(x, ast.Node))


def walk(node: ast.Node) -> Iterator[ast.Node]:
    """``node`` and all its descendants, depth first, in source order."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(reversed(list(children(current))))


def dump(node: ast.Node, indent: int = 0) -> str:
    """An indented text view: one node per line with its position and scalar fields."""
    lines: list[str] = []
    _dump(node, indent, lines, "")
    return "\n".join(lines)


def _dump(node: ast.Node, depth: int, lines: list[str], label: str) -> None:
    scalars = []
    nested: list[tuple[str, ast.Node | tuple[object, ...]]] = []
    for f in fields(node):
        if f.name == "span":
            continue
        value = getattr(node, f.name)
        if isinstance(value, ast.Node) or (
            isinstance(value, tuple) and any(isinstance(v, (ast.Node, tuple)) for v in value)
        ):
            nested.append((f.name, value))
        elif isinstance(value, ast.Name):
            scalars.append(f"{f.name}={value.text!r}")
        elif value is not None and value != () and f.name not in ("target_span",):
            scalars.append(
                f"{f.name}={value!r}" if not isinstance(value, str) else f"{f.name}={value!r}"
            )
    text = node.text if isinstance(node, ast.Name) else None
    head = f"{'  ' * depth}{label}{type(node).__name__}"
    head += f" {text!r}" if text is not None else ""
    head += f" @{node.span.line}:{node.span.column}"
    if scalars and text is None:
        head += " " + " ".join(scalars)
    lines.append(head)
    for name, value in nested:
        if isinstance(value, ast.Node):
            _dump(value, depth + 1, lines, f"{name}: ")
        else:
            for item in value:
                if isinstance(item, ast.Node):
                    _dump(item, depth + 1, lines, f"{name}: ")
                elif isinstance(item, tuple):
                    for sub in item:
                        if isinstance(sub, ast.Node):
                            _dump(sub, depth + 1, lines, f"{name}: ")
