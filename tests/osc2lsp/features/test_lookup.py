"""The position lookup by bisection gives ``visibility.node_path``'s answer."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from osc2check.semantics.visibility import node_path
from osc2lsp.features.lookup import declaration_index, path_at
from tests.osc2lsp.lsp_helpers import REPO, seed_text, snapshot

SYNTAX_CASES = sorted((REPO / "tests" / "osc2check" / "cases" / "syntax").glob("*.osc"))


def _same_everywhere(text: str) -> None:
    snap = snapshot(text)
    for offset in range(len(text) + 1):
        assert [id(n) for n in path_at(snap, offset)] == [
            id(n) for n in node_path(snap.ast, offset)
        ], offset


def test_every_offset_of_the_seed_and_the_syntax_cases_finds_the_same_nodes():
    for text in [seed_text(), *(p.read_text("utf-8", "replace") for p in SYNTAX_CASES)]:
        _same_everywhere(text)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2000),
    st.integers(0, 8),
    st.sampled_from(["", "(", ")", ":", "\n", "\n    ", "x", "[", "#", "\n  ", "\t"]),
)
def test_damaged_texts_find_the_same_nodes(at, length, inserted):
    text = seed_text()
    at = at % (len(text) + 1)
    _same_everywhere(text[:at] + inserted + text[at + length :])


def test_the_index_is_kept_with_the_snapshot():
    snap = snapshot(seed_text())
    assert declaration_index(snap) is declaration_index(snap)
    assert len(declaration_index(snap).starts) == len(snap.ast.declarations)
