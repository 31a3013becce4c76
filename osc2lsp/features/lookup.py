"""The nodes at a position of a snapshot, found by binary search.

``osc2check.semantics.visibility.node_path`` walks the children of each node in
order, and for every top-level declaration before the position follows its last
children down to find where it ends (``extent``): about 10 ms per hover on a
10,000-line document. Here each snapshot keeps, once, where its top-level
declarations start and how far each reaches; a position finds its declaration
by bisection and only that declaration is walked. The answer is
``visibility.node_path``'s (``tests/osc2lsp/features/test_lookup.py``).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass
from itertools import accumulate

from osc2check.semantics.visibility import extent, node_path
from osc2check.syntax import ast
from osc2lsp.snapshot import Snapshot


@dataclass(frozen=True, slots=True)
class DeclarationIndex:
    """Where the top-level declarations of a file start and reach, in order."""

    declarations: tuple[ast.Declaration, ...]
    starts: list[int]
    reaches: list[int]  # each one's extent (its span, or a last child reaching further)
    furthest: list[int]  # the largest extent up to each index (never decreasing)

    @classmethod
    def of(cls, root: ast.File) -> DeclarationIndex:
        declarations = root.declarations
        reaches = [extent(d) for d in declarations]
        return cls(
            declarations,
            [d.span.start for d in declarations],
            reaches,
            list(accumulate(reaches, max)),
        )

    def at(self, offset: int) -> ast.Declaration | None:
        """The declaration ``node_path`` would step into at ``offset``: the first that
        contains it, else the first that ends right at it."""
        last = bisect.bisect_right(self.starts, offset) - 1  # the last to start at or before
        first = bisect.bisect_left(self.furthest, offset)  # the first to reach it
        touching = None
        for i in range(first, last + 1):
            reach = self.reaches[i]
            if reach > offset:
                return self.declarations[i]
            if reach == offset and touching is None:
                touching = self.declarations[i]
        return touching


def declaration_index(snapshot: Snapshot) -> DeclarationIndex:
    """The snapshot's index (built on first use and kept with the snapshot)."""
    index = snapshot._cache.get("declaration index")
    if index is None:
        index = snapshot._cache["declaration index"] = DeclarationIndex.of(snapshot.ast)
    assert isinstance(index, DeclarationIndex)
    return index


def path_at(snapshot: Snapshot, offset: int) -> list[ast.Node]:
    """The nodes from the snapshot's file down to the innermost one at ``offset``, as
    ``visibility.node_path(snapshot.ast, offset)`` gives them."""
    root = snapshot.ast
    declaration = declaration_index(snapshot).at(offset)
    if declaration is None:
        return [root]
    return [root, *node_path(declaration, offset)]
