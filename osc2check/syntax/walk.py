"""Generic traversal of AST nodes, and the ``--dump-ast`` text view."""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import fields
from operator import attrgetter
from typing import Any

from osc2check.syntax import ast

#: the types a field may be annotated with that never hold a node (walk skips it)
_SCALARS = frozenset({"bool", "float", "int", "str", "None", "Fraction", "Span"})
_VALUES: dict[type, Callable[[Any], tuple[object, ...]]] = {}


def _values_of(cls: type) -> Callable[[Any], tuple[object, ...]]:
    """A function giving the values of ``cls``'s fields that may hold nodes, in order: a
    field whose annotation names only scalar types is left out (about half of them, and
    half of a walk's time)."""
    names = tuple(
        f.name
        for f in fields(cls)
        if f.name != "span" and not set(re.findall(r"\w+", str(f.type))) <= _SCALARS
    )
    values: Callable[[Any], tuple[object, ...]]
    if not names:
        values = _no_values
    elif len(names) == 1:
        one = attrgetter(names[0])
        values = lambda node: (one(node),)  # noqa: E731
    else:
        values = attrgetter(*names)
    _VALUES[cls] = values
    return values


def _no_values(node: object) -> tuple[object, ...]:
    return ()


def _children(node: ast.Node) -> list[ast.Node]:
    values = _VALUES.get(type(node)) or _values_of(type(node))
    found: list[ast.Node] = []
    for value in values(node):
        if isinstance(value, ast.Node):
            found.append(value)
        elif isinstance(value, tuple):
            for item in value:
                if isinstance(item, ast.Node):
                    found.append(item)
                elif isinstance(item, tuple):
                    found.extend([x for x in item if isinstance(x, ast.Node)])
    return found


def children(node: ast.Node) -> Iterator[ast.Node]:
    """The direct child nodes of ``node``, in source order."""
    return iter(_children(node))


def walk(node: ast.Node) -> Iterator[ast.Node]:
    """``node`` and all its descendants, depth first, in source order."""
    stack = [node]
    pop = stack.pop
    extend = stack.extend
    while stack:
        current = pop()
        yield current
        found = _children(current)
        if found:
            found.reverse()
            extend(found)


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
