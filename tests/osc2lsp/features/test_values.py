"""Constant folding of physical values."""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2lsp.features.values import describe, evaluate, format_number, in_unit, value_of
from tests.osc2lsp.lsp_helpers import seed_text, snapshot


def _value(text: str, name: str):
    snap = snapshot(text)
    entry = next(e for e in snap.names if e.name.text == name)
    return value_of(snap.model, entry.symbol)


def test_v_npc_fast_folds_exactly_with_the_library_factors():
    q = _value(seed_text(), "v_npc_fast")
    snap = snapshot(seed_text())
    kph, mph = snap.model.unit("kph"), snap.model.unit("mph")
    assert q.si == 35 * kph.factor + Fraction("12.42") * mph.factor
    assert q.unit is kph
    assert describe(q).startswith("≈ 55.0 kph")


def test_folding_follows_names_products_and_signs():
    text = (
        "import osc.standard\nscenario s:\n    a: length = 5m\n"
        "    b: length = (a * 3) - 3m\n    c: length = -b / 2\n    d: length = d + 1m\n"
    )
    assert _value(text, "b").si == 12 and _value(text, "c").si == -6
    assert _value(text, "d") is None  # a cycle does not fold


@pytest.mark.parametrize(
    "value, text",
    [
        (Fraction(35), "35"),
        (Fraction("12.42"), "12.42"),
        (Fraction(1, 3), "≈ 0.333"),
        (Fraction(549878, 10000) + Fraction(1, 10**8), "≈ 55.0"),
        (Fraction(-5, 2), "-2.5"),
    ],
)
def test_number_formatting(value, text):
    assert format_number(value) == text


def test_evaluate_literal_in_its_unit():
    text = "import osc.standard\nscenario s:\n    v: speed = 36kph\n"
    snap = snapshot(text)
    literal = next(e for e in snap.names if e.name.text == "v").symbol.default
    q = evaluate(snap.model, literal)
    assert q.si == 10 and in_unit(q, q.unit) == 36 and describe(q) == "36 kph (10 m/s)"
