"""``walk`` skips the fields whose annotation names only scalar types: on every example
and library file it yields what a walk through every field yields, in the same order."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import pytest

from osc2check.syntax import ast, parse, walk

ROOT = Path(__file__).parents[3]
FILES = sorted([*ROOT.glob("examples/**/*.osc"), *ROOT.glob("stdlib/**/*.osc")])


def every_field(node: ast.Node) -> list[ast.Node]:
    """The walk through every field of every node (the reference)."""
    found = [node]
    for f in fields(node):
        value = getattr(node, f.name)
        items = value if isinstance(value, tuple) else (value,)
        for item in items:
            for sub in item if isinstance(item, tuple) else (item,):
                if isinstance(sub, ast.Node) and f.name != "span":
                    found.extend(every_field(sub))
    return found


def test_there_are_files_to_walk():
    assert len(FILES) > 20


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_walk_yields_every_node_in_source_order(path):
    tree = parse(path.read_text(encoding="utf-8"), path.as_uri()).ast
    assert [id(n) for n in walk(tree)] == [id(n) for n in every_field(tree)]
