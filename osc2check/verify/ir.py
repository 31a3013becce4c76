"""The terms, variables and constraints of a constraint problem, independent of any solver.

Terms are small immutable trees over exact rationals. Every constraint keeps
the span and text it came from, so a solver's unsatisfiable core maps back to
source lines. A ``problem.ConstraintProblem`` holds them for one scenario.
"""

from __future__ import annotations

import operator
from dataclasses import dataclass
from fractions import Fraction
from typing import TypedDict

from osc2check.numbers import MAX_VALUE_BITS, bits, representable
from osc2check.source import Span


@dataclass(frozen=True, slots=True)
class Var:
    """A parameter of the instance: ``hero.vehicle_category``, ``lag``, ``npc@start.lane``."""

    name: str
    sort: str  # "real" | "int" | "bool"
    unit: str = ""  # the unit the witness shows the value in (SI when empty)
    unit_factor: Fraction = Fraction(1)
    unit_offset: Fraction = Fraction(0)
    enum: tuple[tuple[str, int], ...] = ()  # member names and values of an enum parameter
    is_string: bool = False  # a string parameter, encoded as the number of its constant
    span: Span | None = None  # where the parameter is declared

    def __hash__(self) -> int:  # a problem has one variable per name; hash only that
        return hash(self.name)


class VarDetails(TypedDict, total=False):
    """The optional fields of a ``Var`` but its span, as ``ConstraintProblem.var`` takes them."""

    unit: str
    unit_factor: Fraction
    unit_offset: Fraction
    enum: tuple[tuple[str, int], ...]
    is_string: bool


@dataclass(frozen=True, slots=True)
class Const:
    value: Fraction | bool


# One item of a list literal bound to a list member: ("ref", path of a struct parameter)
# or ("value", an exact constant; an enum member by name)
ListItem = tuple[str, "Fraction | bool | str"]


@dataclass(frozen=True, slots=True)
class Ref:
    var: Var


@dataclass(frozen=True, slots=True)
class Op:
    """``op`` over ``args``: + - * / % neg, == != < <= > >=, and or not =>, ite.

    ``/`` is exact division (of integers too: ``7 / 2`` is 7/2) and ``%`` the remainder
    of floored division (``a - b * floor(a / b)``, the sign of ``b``), as the constants
    evaluator has them. Neither has a value when its divisor is 0: ``guarded`` makes a
    constraint false there.
    """

    op: str
    args: tuple[Term, ...]


Term = Const | Ref | Op

TRUE = Const(True)
_ZERO = Const(Fraction(0))


_SMALL = {i: Const(Fraction(i)) for i in range(-8, 65)}


def const(value: bool | int | float | Fraction) -> Const:
    if isinstance(value, int) and not isinstance(value, bool) and value in _SMALL:
        return _SMALL[value]
    return Const(value if isinstance(value, (bool, Fraction)) else Fraction(value))


def op(name: str, *args: Term) -> Op:
    return Op(name, tuple(args))


def minus(a: Term, b: Term) -> Term:
    """``a - b``, computed when both are numbers."""
    if (
        isinstance(a, Const)
        and isinstance(b, Const)
        and not isinstance(a.value, bool)
        and not isinstance(b.value, bool)
    ):
        return const(a.value - b.value)
    return op("-", a, b)


def variables(term: Term) -> set[Var]:
    """The variables a term mentions."""
    found: set[Var] = set()
    seen: set[int] = set()  # operations already walked: a term may share subterms
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Ref):
            found.add(t.var)
        elif isinstance(t, Op) and id(t) not in seen:
            seen.add(id(t))
            stack.extend(t.args)
    return found


def names(term: Term) -> set[str]:
    """The names of the variables a term mentions."""
    found: set[str] = set()
    seen: set[int] = set()  # operations already walked: a term may share subterms
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Ref):
            found.add(t.var.name)
        elif isinstance(t, Op) and id(t) not in seen:
            seen.add(id(t))
            stack.extend(t.args)
    return found


def is_nonlinear(term: Term) -> bool:
    """Whether two non-constant factors are multiplied somewhere in ``term``, or something
    is divided by (or taken modulo) an unknown."""
    seen: set[int] = set()
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Op) and id(t) not in seen:
            seen.add(id(t))
            if t.op == "*" and sum(bool(names(a)) for a in t.args) > 1:
                return True
            if t.op in ("/", "%") and names(t.args[1]):
                return True
            stack.extend(t.args)
    return False


_VARIABLE_BITS = 64  # what a variable's value counts for in ``fits``
_FOLDED = {"+": operator.add, "-": operator.sub, "*": operator.mul}


def fits(term: Term) -> bool:
    """Whether the exact numbers ``term`` computes stay within the budget of
    ``osc2check.numbers``: a product adds its factors' sizes, a sum takes the larger
    and one bit (its variables counted at 64 bits), and the value of each part made of
    constants alone is ``representable``."""
    size: dict[int, int] = {}
    value: dict[int, Fraction | None] = {}  # the parts made of numeric constants alone
    stack: list[tuple[Term, bool]] = [(term, False)]
    while stack:
        t, done = stack.pop()
        if isinstance(t, Const):
            number = None if isinstance(t.value, bool) else t.value
            size[id(t)], value[id(t)] = (1 if number is None else bits(number)), number
        elif isinstance(t, Ref):
            size[id(t)], value[id(t)] = _VARIABLE_BITS, None
        elif not done:
            stack.append((t, True))
            stack.extend((a, False) for a in t.args if id(a) not in size)
        else:
            sizes = [size[id(a)] for a in t.args]
            grown = sum(sizes) if t.op in ("*", "/", "%") else max(sizes) + 1
            folded = (
                _fold(t.op, [value[id(a)] for a in t.args]) if grown <= MAX_VALUE_BITS else None
            )
            if grown > MAX_VALUE_BITS or (folded is not None and not representable(folded)):
                return False
            size[id(t)], value[id(t)] = grown, folded
    return True


def _fold(name: str, args: list[Fraction | None]) -> Fraction | None:
    """The value of ``name`` over constant numbers, or None (not only constants, not
    arithmetic, a division by zero)."""
    if any(a is None for a in args):
        return None
    numbers = [a for a in args if a is not None]
    if name == "neg":
        return -numbers[0]
    if name in _FOLDED:
        return Fraction(_FOLDED[name](numbers[0], numbers[1]))
    if name in ("/", "%") and numbers[1] != 0:
        return numbers[0] / numbers[1] if name == "/" else numbers[0] % numbers[1]
    return None


def divisors(term: Term) -> list[Term]:
    """The divisors of the ``/`` and ``%`` in ``term`` that are not non-zero constants."""
    found: list[Term] = []
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Op):
            if t.op in ("/", "%"):
                d = t.args[1]
                if not (isinstance(d, Const) and not isinstance(d.value, bool) and d.value != 0):
                    found.append(d)
            stack.extend(t.args)
    return found


def guarded(term: Term) -> Term:
    """``term``, false wherever one of its divisions would divide by zero.

    A quotient or remainder by 0 has no value (the exact evaluator refuses it), so a
    constraint that would need one does not hold; the solver must not give the divisor
    the value 0 to satisfy it (z3 leaves ``x / 0`` unspecified).
    """
    found = divisors(term)
    if not found:
        return term
    conditions: list[Term] = []
    for d in found:
        if isinstance(d, Const):
            return Const(False)  # a constant zero divisor: never holds
        condition = Op("!=", (d, _ZERO))
        if condition not in conditions:
            conditions.append(condition)
    return Op("and", (*conditions, term))


@dataclass(frozen=True, slots=True)
class Constraint:
    """One source-level constraint.

    ``kind`` is "keep", "default", "argument", "modifier", "declaration" (a field's
    `= value`), "domain" or "placement" (implicit constraints of the road and the
    vehicles), "timing" (a written duration, overlap or event time, with the rules
    of the runner it must keep: ``verify.timing``) or "definition" (a rule that only
    defines a variable of the timing model: never part of a conflict). A constraint
    on a parameter alone (``p == v`` or ``p in [a..b]``, and every argument) records
    that parameter in ``subject``: a hard one replaces the parameter's defaults.
    ``origin`` names the declaration body the constraint is
    written in; two defaults of one parameter in one body conflict (C404).
    """

    term: Term
    span: Span
    kind: str
    text: str
    strength: str = "hard"  # "hard" | "default"
    subject: Var | None = None
    explanation: str = ""  # for implicit constraints: where the rule comes from
    rule: str = ""  # implicit constraints: "lane-range", "road-extent", "max-speed", "overlap"
    origin: str = ""
    # implicit constraints: the written constraints that made them apply (the keep that
    # makes an actor a truck, for the truck's top speed); conflicts name them too
    because: tuple[Constraint, ...] = ()
    # a reading the toolkit chose where the scenario leaves the state open (the starts
    # after its first wait, as if every actor kept its speed meanwhile), named by what it
    # assumes: a reading's constraints hold together, or, when they take part in a
    # conflict, none of them (``ConstraintProblem.firm``); "" for every other constraint
    tentative: str = ""


@dataclass(frozen=True, slots=True)
class Skipped:
    """A constraint that lowering could not encode: where it is written, its text, and
    why. Every one is reported (C411), and the witness says it was not verified."""

    span: Span
    text: str
    reason: str

    def to_json(self) -> dict[str, object]:
        """Where it is written, its text and why (the JSON output's ``unverified``)."""
        return {
            "path": self.span.uri,
            "line": self.span.line,
            "column": self.span.column,
            "text": self.text,
            "reason": self.reason,
        }
