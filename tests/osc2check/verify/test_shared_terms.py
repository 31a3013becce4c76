"""Terms that share subterms (an expanded schedule: each phase's time is built from the
one before it) are walked once per distinct operation, not once per path to it: a
tree walk of such a term is exponential in its depth (CARLA's
cut_in_and_slow_range.osc took about two minutes to draw its witness)."""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.verify import ir, propagate

DEPTH = 22  # 4 million paths: a walk along each takes seconds, and the counts tell


def _chain(start: ir.Term, depth: int = DEPTH) -> ir.Term:
    """``t(k+1) = t(k) + t(k)``: ``depth`` distinct operations, 2**depth paths."""
    term = start
    for _ in range(depth):
        term = ir.op("+", term, term)
    return term


def _ref(name: str, sort: str = "real") -> ir.Ref:
    return ir.Ref(ir.Var(name, sort))


def test_fold_folds_each_shared_operation_once(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []
    real = propagate._fold_op
    monkeypatch.setattr(propagate, "_fold_op", lambda t, v, m: calls.append(t.op) or real(t, v, m))
    term = _chain(_ref("x"))
    assert propagate.fold(term, {"x": Fraction(3)}) == ir.const(3 * 2**DEPTH)
    assert len(calls) == DEPTH
    calls.clear()
    open_term = propagate.fold(term, {})
    assert ir.names(open_term) == {"x"} and len(calls) == DEPTH


def test_a_linear_form_of_a_shared_term(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []
    real = propagate._linear_op
    monkeypatch.setattr(propagate, "_linear_op", lambda t, m: calls.append(t.op) or real(t, m))
    term = ir.op("-", _chain(_ref("x")), ir.const(1))
    assert propagate.linear(term) == ({"x": Fraction(2**DEPTH)}, Fraction(-1))
    assert len(calls) == DEPTH + 1


def test_names_variables_and_nonlinearity_of_a_shared_term() -> None:
    linear = _chain(ir.op("+", _ref("x"), _ref("y")))
    assert ir.names(linear) == {"x", "y"}
    assert {v.name for v in ir.variables(linear)} == {"x", "y"}
    assert not ir.is_nonlinear(linear)
    product = ir.op("+", _chain(_ref("x")), ir.op("*", _ref("x"), _ref("y")))
    assert ir.is_nonlinear(product)
    # the product under the shared part: found through it
    assert ir.is_nonlinear(_chain(ir.op("*", _ref("x"), _ref("y"))))
