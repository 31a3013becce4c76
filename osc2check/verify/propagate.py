"""Find a model of a constraint set without a solver, when an easy one exists.

Most scenarios fix their parameters by equalities (defaults, arguments, `var`
initialisers), bound the others by intervals (ranges, the road, the vehicles)
and relate actors by linear equations (gaps, neighbouring lanes). For such a
set a model is found by propagation: solve each equation with one unknown,
then give the first unknown left a value inside its bounds, and repeat. The
model is then checked against every constraint with exact arithmetic, so a
model returned here is a model; when none is found (the set may be
unsatisfiable, or just harder), the z3 backend decides. Nothing here ever
reports a conflict.

The analysis uses this to skip the solver (and loading z3) for scenarios that
are plainly satisfiable; witnesses and conflicts always come from z3.
"""

from __future__ import annotations

import math
import random
from collections.abc import Collection, Iterator, Mapping
from fractions import Fraction

from osc2check.verify import ir

Linear = tuple[dict[str, Fraction], Fraction]  # sum of coefficient * variable, plus constant
# each comparison with its sides swapped
FLIPPED = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}
_MAX_STEPS = 10_000
_ZERO, _ONE = Fraction(0), Fraction(1)


class _Unsupported(Exception):
    pass


def linear(term: ir.Term) -> Linear | None:
    """``term`` as a linear form over its numeric variables, or None."""
    try:
        return _linear(term, {})
    except _Unsupported:
        return None


def _linear(term: ir.Term, memo: dict[int, Linear]) -> Linear:
    """``linear``'s form of ``term``; ``memo`` holds it for each operation of the term
    already seen (an expanded schedule shares subterms: a tree walk of it is exponential)."""
    if isinstance(term, ir.Op):
        found = memo.get(id(term))
        if found is None:
            found = memo[id(term)] = _linear_op(term, memo)
        return found
    if isinstance(term, ir.Const):
        if isinstance(term.value, bool):
            raise _Unsupported
        return {}, term.value
    if isinstance(term, ir.Ref):
        if term.var.sort == "bool":
            raise _Unsupported
        return {term.var.name: _ONE}, _ZERO
    raise _Unsupported


def _linear_op(term: ir.Op, memo: dict[int, Linear]) -> Linear:
    if term.op == "neg":
        coeffs, k = _linear(term.args[0], memo)
        return {v: -c for v, c in coeffs.items()}, -k
    if term.op in ("+", "-"):
        (a, ka), (b, kb) = _linear(term.args[0], memo), _linear(term.args[1], memo)
        sign = 1 if term.op == "+" else -1
        out = dict(a)
        for v, c in b.items():
            out[v] = out.get(v, _ZERO) + sign * c
        return {v: c for v, c in out.items() if c}, ka + sign * kb
    if term.op == "*":
        (a, ka), (b, kb) = _linear(term.args[0], memo), _linear(term.args[1], memo)
        if a and b:
            raise _Unsupported
        if not a:
            a, ka, b, kb = b, kb, a, ka
        # a * kb (b is a constant)
        return ({v: c * kb for v, c in a.items() if c * kb}, ka * kb)
    if term.op == "/":
        (a, ka), (b, kb) = _linear(term.args[0], memo), _linear(term.args[1], memo)
        if b or not kb:  # by an unknown, or by zero (no value)
            raise _Unsupported
        return ({v: c / kb for v, c in a.items()}, ka / kb)
    raise _Unsupported


def holds(term: ir.Term, values: Mapping[str, Fraction | bool]) -> bool | None:
    """Whether ``term`` is true under ``values``; None when it cannot be evaluated there
    (a variable it mentions has no value, a division by zero, a type that does not fit)."""
    try:
        return evaluate(term, values) is True
    except (KeyError, TypeError, ZeroDivisionError):
        return None


def evaluate(term: ir.Term, values: Mapping[str, Fraction | bool]) -> Fraction | int:
    """The value of ``term`` under ``values`` (every variable it mentions must be there);
    a bool is an int, and arithmetic on one gives an int."""
    if isinstance(term, ir.Const):
        return term.value
    if isinstance(term, ir.Ref):
        return values[term.var.name]
    op, args = term.op, term.args
    if op == "and":
        return all(evaluate(a, values) for a in args)
    if op == "or":
        return any(evaluate(a, values) for a in args)
    if op == "not":
        return not evaluate(args[0], values)
    if op == "=>":
        return (not evaluate(args[0], values)) or bool(evaluate(args[1], values))
    if op == "ite":
        return evaluate(args[1], values) if evaluate(args[0], values) else evaluate(args[2], values)
    if op == "neg":
        return -evaluate(args[0], values)
    a = evaluate(args[0], values)
    b = evaluate(args[1], values)
    match op:
        case "+":
            return a + b
        case "-":
            return a - b
        case "*":
            return a * b
        case "/":
            return Fraction(a) / b  # ZeroDivisionError for 0, as ``guarded`` has it
        case "%":
            return a % b  # floored, the sign of ``b`` (Python's, the evaluator's)
        case "==":
            return a == b
        case "!=":
            return a != b
        case "<":
            return a < b
        case "<=":
            return a <= b
        case ">":
            return a > b
        case ">=":
            return a >= b
    raise ValueError(f"unknown operator {op}")


class Atom:
    """One conjunct: ``form op 0`` (linear), a finite set of values of one variable,
    a boolean literal, or anything else (only checked at the end). An equation that is
    not linear keeps its ``term``: once all but one of its unknowns have values it may
    be (``gap == closing * headway`` with the closing speed and the headway drawn); so
    does a disjunction, which may then be one equation (``choice != 1 or lane == 2``,
    a ``one_of`` member's start, with the member drawn)."""

    __slots__ = ("kind", "form", "op", "var", "values", "names", "unknown", "term")

    def __init__(
        self,
        kind: str,
        names: tuple[str, ...],
        form: Linear | None = None,
        op: str = "",
        var: str = "",
        values: tuple[Fraction | bool, ...] = (),
        term: ir.Term | None = None,
    ):
        self.kind = kind
        self.form: Linear | None = form
        self.op = op
        self.var = var
        self.values = values
        self.names: tuple[str, ...] = names
        self.unknown = len(names)
        self.term = term


def split_conjuncts(term: ir.Term, out: list[ir.Term]) -> None:
    """Append the conjuncts of ``term`` (its arguments, when it is an `and`) to ``out``."""
    if isinstance(term, ir.Op) and term.op == "and":
        for a in term.args:
            split_conjuncts(a, out)
    else:
        out.append(term)


def atom_of(term: ir.Term) -> Atom:
    """``term`` as an :class:`Atom`."""
    if isinstance(term, ir.Op) and term.op in FLIPPED:  # the common `x op constant`
        left, right = term.args
        if (
            isinstance(left, ir.Ref)
            and isinstance(right, ir.Const)
            and left.var.sort != "bool"
            and not isinstance(right.value, bool)
        ):
            name = left.var.name
            return Atom(
                "eq" if term.op == "==" else "cmp",
                (name,),
                form=({name: _ONE}, -right.value),
                op=term.op,
            )
    names = tuple(sorted(ir.names(term)))
    if isinstance(term, ir.Ref) and term.var.sort == "bool":
        return Atom("bool", names, var=term.var.name, values=(True,))
    if isinstance(term, ir.Op):
        if (
            term.op == "not"
            and isinstance(term.args[0], ir.Ref)
            and term.args[0].var.sort == "bool"
        ):
            return Atom("bool", names, var=term.args[0].var.name, values=(False,))
        if term.op in FLIPPED:
            left, right = term.args
            if (
                term.op == "=="
                and isinstance(left, ir.Ref)
                and left.var.sort == "bool"
                and isinstance(right, ir.Const)
                and isinstance(right.value, bool)
            ):
                return Atom("bool", names, var=left.var.name, values=(right.value,))
            a, b = linear(left), linear(right)
            if a is not None and b is not None:
                form = dict(a[0])
                for v, c in b[0].items():
                    form[v] = form.get(v, _ZERO) - c
                form = {v: c for v, c in form.items() if c}
                return Atom(
                    "eq" if term.op == "==" else "cmp",
                    tuple(sorted(form)),
                    form=(form, a[1] - b[1]),
                    op=term.op,
                )
        if term.op == "or" and names and len(names) == 1:
            values = []
            for alt in term.args:
                if not (
                    isinstance(alt, ir.Op)
                    and alt.op == "=="
                    and isinstance(alt.args[0], ir.Ref)
                    and isinstance(alt.args[1], ir.Const)
                ):
                    break
                values.append(alt.args[1].value)
            else:
                return Atom("set", names, var=names[0], values=tuple(values))
        if term.op in ("==", "or"):
            return Atom("other", names, term=term)
    return Atom("other", names)


def _van_der_corput(k: int) -> Fraction:
    """The k-th point of the van der Corput sequence in (0, 1): 1/2, 1/4, 3/4, 1/8, ..."""
    k += 1
    numerator, denominator = 0, 1
    while k:
        k, bit = divmod(k, 2)
        numerator, denominator = numerator * 2 + bit, denominator * 2
    return Fraction(numerator, denominator)


_SPREAD = [_van_der_corput(k) for k in range(256)]


def _spread(k: int) -> Fraction:
    return _SPREAD[k] if k < len(_SPREAD) else _van_der_corput(k)


def fold(term: ir.Term, values: Mapping[str, Fraction | bool]) -> ir.Term:
    """``term`` with the variables of ``values`` replaced by their values, and what that
    makes constant computed (``ite`` on a known condition is its branch)."""
    return _fold(term, values, {})


def _fold(
    term: ir.Term, values: Mapping[str, Fraction | bool], memo: dict[int, ir.Term]
) -> ir.Term:
    """``fold``; ``memo`` holds the result for each operation of ``term`` already folded
    (shared subterms are folded once)."""
    if isinstance(term, ir.Ref):
        value = values.get(term.var.name)
        return term if value is None else ir.const(value)
    if not isinstance(term, ir.Op):
        return term
    found = memo.get(id(term))
    if found is None:
        found = memo[id(term)] = _fold_op(term, values, memo)
    return found


def _fold_op(
    term: ir.Op, values: Mapping[str, Fraction | bool], memo: dict[int, ir.Term]
) -> ir.Term:
    if term.op == "ite":
        condition = _fold(term.args[0], values, memo)
        if isinstance(condition, ir.Const):
            return _fold(term.args[1] if condition.value else term.args[2], values, memo)
        return ir.Op(
            "ite", (condition, _fold(term.args[1], values, memo), _fold(term.args[2], values, memo))
        )
    args = tuple(_fold(a, values, memo) for a in term.args)
    if term.op in ("and", "or"):
        absorbing = term.op == "or"  # True absorbs `or`, False absorbs `and`
        kept = []
        for a in args:
            if isinstance(a, ir.Const):
                if bool(a.value) is absorbing:
                    return ir.const(absorbing)
                continue
            kept.append(a)
        if not kept:
            return ir.const(not absorbing)
        return kept[0] if len(kept) == 1 else ir.Op(term.op, tuple(kept))
    if all(isinstance(a, ir.Const) for a in args):
        try:
            folded = evaluate(ir.Op(term.op, args), {})
        except (ZeroDivisionError, TypeError):
            return ir.Op(term.op, args)
        return ir.const(folded if isinstance(folded, (bool, Fraction)) else Fraction(folded))
    return ir.Op(term.op, args)


class Prepared:
    """A constraint set split into atoms once, for many ``find_model`` calls.

    A conjunct that is not linear (``v <= ite(category == truck, 25, ...)``,
    ``gap == closing * ttc0``) is folded with the values that equations fix from
    constants alone first (a field's ``ttc0: time = 4s``), so that a vehicle's category
    chosen by a keep gives its speed an upper bound to draw under, and a product with a
    constant field is linear. The original conjuncts are what a model is checked
    against. Variables are drawn in the order they are first mentioned, those in
    ``first`` (choices that others depend on) before the rest and those in ``last``
    (which equations define from the others) after it.
    """

    def __init__(
        self, terms: list[ir.Term], last: Collection[str] = (), first: Collection[str] = ()
    ):
        self.conjuncts: list[ir.Term] = []
        for t in terms:
            split_conjuncts(t, self.conjuncts)
        self.atoms = [atom_of(t) for t in self.conjuncts]
        if any(a.kind == "other" for a in self.atoms):
            self.atoms = _folded(self.conjuncts, self.atoms)
        self.by_var: dict[str, list[Atom]] = {}
        order: list[str] = []
        for a in self.atoms:
            for name in a.names:
                if name not in self.by_var:
                    self.by_var[name] = []
                    order.append(name)
                self.by_var[name].append(a)
        ahead = [n for n in order if n in first]
        self.order = ahead + [n for n in order if n not in last and n not in first]
        self.order += [n for n in order if n in last and n not in first]


def find_model(
    variables: dict[str, ir.Var],
    terms: list[ir.Term] | Prepared,
    rng: random.Random | None = None,
    preferred: dict[str, tuple[Fraction, Fraction]] | None = None,
) -> dict[str, Fraction | bool] | None:
    """A model of the conjunction of ``terms``, or None when none is found easily.

    Without ``rng`` the choices are fixed (points spread over each variable's bounds in
    a fixed sequence); with it they are drawn at random, so a seeded ``rng`` draws one
    model of many (the sampler's first try). A variable with a ``preferred`` range is
    drawn inside it where its bounds allow (a plausible value, never a constraint).
    ``terms`` may be a ``Prepared`` set, to draw many models of one set.
    """
    preferred = preferred or {}
    prepared = terms if isinstance(terms, Prepared) else Prepared(terms)
    conjuncts, atoms, by_var, order = (
        prepared.conjuncts,
        prepared.atoms,
        prepared.by_var,
        prepared.order,
    )
    for a in atoms:
        a.unknown = len(a.names)
    values: dict[str, Fraction | bool] = {}
    ready = [a for a in atoms if a.kind in ("eq", "bool") and a.unknown == 1]
    picks = 0
    steps = 0
    next_pick = 0

    def assign(name: str, value: Fraction | bool) -> bool:
        var = variables.get(name)
        if (
            var is not None
            and var.sort == "int"
            and (isinstance(value, bool) or Fraction(value).denominator != 1)
        ):
            return False
        values[name] = value
        for a in by_var[name]:
            a.unknown -= 1
            if a.unknown == 1 and (a.kind in ("eq", "bool") or a.term is not None):
                ready.append(a)
        return True

    while True:
        steps += 1
        if steps > _MAX_STEPS:
            return None
        if ready:
            a = ready.pop()
            if a.unknown != 1:
                continue
            name = next(n for n in a.names if n not in values)
            if a.kind == "bool":
                if not assign(name, a.values[0]):
                    return None
                continue
            if a.kind == "other":  # an equation linear in its last unknown, or left to check
                assert a.term is not None  # only equations are made ready
                solved = atom_of(fold(a.term, values))
                if solved.kind != "eq" or solved.names != (name,):
                    continue
                a = solved
            assert a.form is not None  # an equation has its linear form
            coeffs, constant = a.form
            rest = constant + sum(c * values[v] for v, c in coeffs.items() if v != name)
            if not assign(name, -rest / coeffs[name]):
                return None
            continue
        while next_pick < len(order) and order[next_pick] in values:
            next_pick += 1
        if next_pick >= len(order):
            break
        name = order[next_pick]
        where = _spread(picks) if rng is None else Fraction(rng.randint(1, 999_999), 1_000_000)
        value = _choose(
            variables.get(name), name, by_var[name], values, where, rng, preferred.get(name)
        )
        picks += 1
        if value is None or not assign(name, value):
            return None
    try:
        if all(evaluate(t, values) is True for t in conjuncts):
            return values
    except (KeyError, ZeroDivisionError, TypeError):
        return None
    return None


def _choose(
    var: ir.Var | None,
    name: str,
    atoms: list[Atom],
    values: dict[str, Fraction | bool],
    where: Fraction,
    rng: random.Random | None = None,
    preferred: tuple[Fraction, Fraction] | None = None,
) -> Fraction | bool | None:
    """A value for ``name`` inside the bounds its one-variable constraints give (inside
    ``preferred`` too where those bounds allow)."""
    sort = var.sort if var is not None else "real"
    if sort == "bool":
        for a in atoms:
            if a.kind == "bool" and a.unknown == 1:
                return a.values[0]
        return rng.random() < 0.5 if rng is not None else False
    low: Fraction | None = None
    high: Fraction | None = None
    low_strict = high_strict = False
    allowed: set[Fraction | bool] | None = None
    excluded: set[Fraction | bool] = set()
    for a in atoms:
        if a.unknown != 1:
            continue
        if a.kind == "set":
            allowed = set(a.values) if allowed is None else allowed & set(a.values)
            continue
        if a.kind not in ("cmp", "eq"):
            continue
        assert a.form is not None  # a comparison has its linear form
        coeffs, constant = a.form
        c = coeffs.get(name)
        if not c:
            continue
        if len(coeffs) == 1:  # the common `x op constant`
            bound = -constant if c == 1 else -constant / c
        else:
            rest = constant + sum(k * values[v] for v, k in coeffs.items() if v != name)
            bound = -rest / c
        op = a.op if c > 0 else FLIPPED[a.op]
        if op == "!=":
            excluded.add(bound)
        elif op == "==":
            allowed = {bound} if allowed is None else allowed & {bound}
        elif op in (">", ">="):
            if low is None or bound > low or (bound == low and op == ">"):
                low, low_strict = bound, op == ">"
        elif high is None or bound < high or (bound == high and op == "<"):
            high, high_strict = bound, op == "<"

    def fits(x: Fraction | bool) -> bool:
        if x in excluded:
            return False
        if low is not None and (x < low or (low_strict and x == low)):
            return False
        if high is not None and (x > high or (high_strict and x == high)):
            return False
        return sort != "int" or Fraction(x).denominator == 1

    if preferred is not None and sort != "bool":
        lo_p = preferred[0] if low is None else max(low, preferred[0])
        hi_p = preferred[1] if high is None else min(high, preferred[1])
        if lo_p <= hi_p:  # the plausible part of the bounds (open ends kept open)
            low, high = lo_p, hi_p
            low_strict = low_strict and low == lo_p and low != preferred[0]
            high_strict = high_strict and high == hi_p and high != preferred[1]
    if allowed is not None:
        fitting = [x for x in sorted(allowed) if fits(x)]
        if not fitting:
            return None
        return fitting[0] if rng is None else rng.choice(fitting)
    if sort == "int":
        lo = None if low is None else (math.floor(low) + 1 if low_strict else math.ceil(low))
        hi = None if high is None else (math.ceil(high) - 1 if high_strict else math.floor(high))
        if lo is not None and hi is not None and lo > hi:
            return None
        candidates = _int_candidates(lo, hi, where)
    elif low is not None and high is not None:
        if low > high:
            return None
        candidates = iter((low + (high - low) * where, (low + high) / 2, low, high))
    elif low is not None:
        candidates = iter((low + 1, low + Fraction(1, 2), low))
    elif high is not None:
        candidates = iter((high - 1, high - Fraction(1, 2), high))
    else:
        candidates = iter((_ZERO, _ONE, -_ONE))
    return next((x for x in candidates if fits(x)), None)


def _folded(conjuncts: list[ir.Term], atoms: list[Atom]) -> list[Atom]:
    """``atoms`` with each non-linear one replaced by the atoms of its conjunct folded with
    the values that equations fix (``determined``): constants, for what follows."""
    known = _propagated([a for a in atoms if a.kind in ("eq", "bool")])
    for a in atoms:
        a.unknown = len(a.names)  # as propagation found them
    if not known:
        return atoms
    result: list[Atom] = []
    for c, a in zip(conjuncts, atoms, strict=True):
        if a.kind != "other" or not any(n in known for n in a.names):
            result.append(a)
            continue
        parts: list[ir.Term] = []
        split_conjuncts(fold(c, known), parts)
        kept = (p for p in parts if not (isinstance(p, ir.Const) and p.value is True))
        result.extend(atom_of(p) for p in kept)
    return result


def determined(terms: list[ir.Term]) -> dict[str, Fraction | bool]:
    """The values that equations fix by propagation from constants alone (no choices)."""
    conjuncts: list[ir.Term] = []
    for t in terms:
        split_conjuncts(t, conjuncts)
    return _propagated([a for a in map(atom_of, conjuncts) if a.kind in ("eq", "bool")])


def _propagated(atoms: list[Atom]) -> dict[str, Fraction | bool]:
    """The values that the equations and boolean literals ``atoms`` fix by propagation."""
    by_var: dict[str, list[Atom]] = {}
    for a in atoms:
        for name in a.names:
            by_var.setdefault(name, []).append(a)
    values: dict[str, Fraction | bool] = {}
    ready = [a for a in atoms if a.unknown == 1]
    while ready:
        a = ready.pop()
        if a.unknown != 1:
            continue
        name = next(n for n in a.names if n not in values)
        if a.kind == "bool":
            value = a.values[0]
        else:
            assert a.form is not None  # an equation has its linear form
            coeffs, constant = a.form
            value = (
                -(constant + sum(c * values[v] for v, c in coeffs.items() if v != name))
                / coeffs[name]
            )
        values[name] = value
        for other in by_var[name]:
            other.unknown -= 1
            if other.unknown == 1:
                ready.append(other)
    return values


def _int_candidates(lo: int | None, hi: int | None, where: Fraction) -> Iterator[Fraction]:
    """Integers to try, the first one chosen by ``where`` when both bounds are known."""
    if lo is not None and hi is not None:
        yield Fraction(min(lo + math.floor((hi - lo + 1) * where), hi))
        for x in range(lo, min(hi, lo + 8) + 1):
            yield Fraction(x)
    elif lo is not None:
        for x in range(lo, lo + 8):
            yield Fraction(x)
    elif hi is not None:
        for x in range(hi, hi - 8, -1):
            yield Fraction(x)
    else:
        for x in (0, 1, -1, 2, -2):
            yield Fraction(x)
