"""Folding ranges."""

from __future__ import annotations

from osc2lsp.features.folding import Fold, folding_ranges
from tests.osc2lsp.lsp_helpers import seed_text


def test_folding_ranges_of_blocks_comments_and_imports():
    text = (
        "import a\nimport b\n\n# one\n# two\nscenario s:\n    x: int\n"
        "    do serial:\n        wait @e\n\n        emit e\n"
    )
    assert folding_ranges(text) == [
        Fold(0, 1, "imports"),
        Fold(3, 4, "comment"),
        Fold(5, 10),
        Fold(7, 10),
    ]


def test_folding_ranges_of_the_seed_and_of_broken_text():
    folds = folding_ranges(seed_text())
    assert Fold(3, 71) in folds and Fold(23, 71) in folds
    assert folding_ranges("scenario s:\n    x: int = (1 +\n") == [Fold(0, 1)]
    assert folding_ranges("") == []
