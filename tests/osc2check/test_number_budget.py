"""Numbers and strings in the grammar cost what their text is worth (``osc2check.numbers``).

``1e99999999`` (ten characters) took four minutes and then "All checks passed"; an
integer of 5,000 digits became 0 in silence; ``1e300kph * 1e300`` crashed the checker
and the runner (a float overflow); products nested a dozen deep took minutes; a string
literal took about 400 bytes of memory per character. A seeded storm of literals checks
the budget's edges against the exact value ``fractions.Fraction`` gives.
"""

from __future__ import annotations

import tracemalloc
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.numbers import MAX_DIGITS, MAX_MAGNITUDE, NumberOutOfRange, exact_number
from osc2check.syntax import parse
from osc2check.syntax.lexer import tokenize


def _scenario(value: str, keep: str = "keep(x < 10)") -> str:
    return (
        "import osc.standard\n"
        "scenario s:\n"
        f"    x: float = {value}\n"
        "    hero: vehicle\n"
        f"    {keep}\n"
        "    do hero.drive(duration: 3s)\n"
    )


def _codes(text: str, verify: bool = True) -> list[str]:
    analysis = analyze([SourceInput("budget.osc", text)], AnalysisOptions(verify=verify))
    return [d.code.code for d in analysis.diagnostics]


@pytest.mark.parametrize(
    "literal",
    [
        "1e9999999",
        "1e99999999",
        "1e99999999999999999999",
        "1e-99999999",
        "4e305",
        "1e99999999kph",
        "1" * 5000,
        "0x" + "f" * 400,
    ],
)
def test_a_number_beyond_the_budget_is_T209_at_once(literal):
    found = _codes(_scenario(literal))
    assert "T209" in found
    assert [
        d.message for d in parse(_scenario(literal), "n.osc").diagnostics if d.code.code == "T209"
    ]


@pytest.mark.parametrize("literal", ["0e99999999", "1e300", "1e-300", "0x2A", "2.5e3kph"])
def test_a_number_within_the_budget_has_its_exact_value(literal):
    assert "T209" not in _codes(_scenario(literal), verify=False)


def test_a_value_computed_beyond_the_range_is_not_verified_and_crashes_nothing():
    text = (
        "import osc.standard\n"
        "scenario s:\n"
        "    hero: vehicle\n"
        "    do hero.drive(duration: 3s) with:\n"
        "        speed(1e300kph * 1e300)\n"
    )
    assert "C411" in _codes(text)


def _product(depth: int, leaf: str) -> str:
    return leaf if depth == 0 else f"({_product(depth - 1, leaf)}*{_product(depth - 1, leaf)})"


@pytest.mark.parametrize("leaf", ["1e300", "x", "(x+1e300)"])
def test_products_nested_deep_are_left_out_of_the_solver_not_computed(leaf):
    """4,096 factors: the exact value would have millions of digits."""
    text = _scenario("1", keep=f"keep(y == {_product(12, leaf)})").replace(
        "    hero: vehicle\n", "    y: float\n    hero: vehicle\n"
    )
    assert "C411" in _codes(text)


def test_a_long_string_literal_is_lexed_in_memory_proportional_to_it():
    """The grammar's STRING is an unrolled loop with possessive repeats."""
    for body in ("a" * 1_000_000, "\\n" * 500_000):
        text = f'x: string = "{body}"\n'
        tracemalloc.start()
        result = tokenize(text)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert [t.type for t in result.tokens if t.type == "STRING"] == ["STRING"]
        assert peak < 4 * len(text) + 1_000_000


def test_string_literals_mean_what_they_meant():
    """The same strings (and the same unclosed ones) as the plain alternation took."""
    for text, value in [
        ('"a\\"b"', 'a"b'),
        ("'it\\'s'", "it's"),
        ('"""one "two" ""three"" """', 'one "two" ""three"" '),
        ("'''a\nb'''", "a\nb"),
        ('"\\\\"', "\\"),
    ]:
        result = parse(f"global s: string = {text}\n", "s.osc")
        assert not result.diagnostics, text
        [decl] = result.ast.declarations
        assert decl.field.default.value == value
    assert [d.code.code for d in parse('global s: string = "a\\"\n', "s.osc").diagnostics] == [
        "P003"
    ]


# ---- a seeded storm of literals at the budget's edges -------------------------------------

_EXPONENTS = [0, 1, -1, 7, -7, MAX_MAGNITUDE - 1, MAX_MAGNITUDE, MAX_MAGNITUDE + 1]
_EXPONENTS += [-MAX_MAGNITUDE, -MAX_MAGNITUDE - 1, -MAX_MAGNITUDE - 2, 10**6, -(10**6), 10**20]


@st.composite
def literals(draw) -> str:
    """A decimal literal: whole digits (a few, or up to past ``MAX_DIGITS``), maybe a
    fraction, maybe an exponent near the budget's edges or far beyond them."""
    long = draw(st.booleans())
    size = draw(st.integers(MAX_DIGITS - 3, MAX_DIGITS + 3) if long else st.integers(1, 6))
    first = draw(st.sampled_from("0123456789"))
    text = first + "7" * (size - 1)
    if draw(st.booleans()):
        text += "." + draw(st.sampled_from(["0", "5", "25", "000"]))
    exponent = draw(st.sampled_from([None, *_EXPONENTS]))
    if exponent is not None:
        text += f"e{exponent}"
    return text


def _within(text: str) -> bool:
    """The budget, worked out the slow way (only for exponents small enough)."""
    mantissa, _, exponent = text.partition("e")
    if len(mantissa.replace(".", "")) > MAX_DIGITS:
        return False
    if exponent and abs(int(exponent)) > 10 * MAX_MAGNITUDE:
        return Fraction(mantissa) == 0
    value = Fraction(text)
    return value == 0 or Fraction(1, 10**MAX_MAGNITUDE) <= abs(value) < 10 ** (MAX_MAGNITUDE + 1)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(literal=literals())
def test_number_storm_each_literal_has_its_exact_value_or_T209(literal):
    if _within(literal):
        assert exact_number(literal) == Fraction(literal)
    else:
        with pytest.raises(NumberOutOfRange):
            exact_number(literal)
    codes = [d.code.code for d in parse(f"global g: float = {literal}\n", "g.osc").diagnostics]
    assert codes == ([] if _within(literal) else ["T209"])


@settings(max_examples=50, derandomize=True, deadline=None)
@given(
    body=st.lists(
        st.sampled_from(["a", "\\n", '\\"', "'", '"', "\\\\", "é", "\t", "\n", "\\"]), max_size=40
    ),
    quote=st.sampled_from(['"', "'", '"""', "'''"]),
    repeat=st.sampled_from([1, 100]),
)
def test_string_storm_never_raises_and_reads_the_body(body, quote, repeat):
    text = f"global s: string = {quote}{''.join(body) * repeat}{quote}\n"
    result = parse(text, "s.osc")
    assert all(d.code.code.startswith("P") for d in result.diagnostics)
