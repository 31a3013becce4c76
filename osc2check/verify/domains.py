"""What the constraints allow each parameter, and which parameters equations relate.

For campaigns (``osc2runner.campaign``), which sweep a scenario's parameters and
say how evenly their runs cover them:

* :func:`domains`: per variable, the bounds that constraints on it alone give (a
  range, the road, a vehicle's top speed) and, when they allow finitely many
  values (a set, an integer range, an enum, a boolean), those values;
* :func:`equations`: the unknowns each equation between unknowns relates, after
  the constants are folded in (a field's ``ttc0: time = 4s`` is a constant, as for
  the sampler): ``gap == (ego_speed - target_speed) * ttc0`` relates ``gap`` and
  ``ego_speed``, so a campaign that sweeps the speed does not sweep the gap too.

Both read the constraints that hold (``z3_backend.active_constraints``), in SI
units, exact, leaving out the readings of open starts (what the scenario allows, not
what the witness prefers).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from osc2check.verify import ir, propagate
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.z3_backend import SolverOutcome, active_constraints, bounds

__all__ = ["MAX_VALUES", "Domain", "domains", "equations"]

MAX_VALUES = 200  # an integer range with more values than this is not listed


@dataclass(frozen=True)
class Domain:
    """A variable's bounds (None: unbounded) and its allowed values when there are
    finitely many (sorted; None otherwise), in SI units."""

    low: Fraction | None
    high: Fraction | None
    values: tuple[Fraction | bool, ...] | None = None


def _active(problem: ConstraintProblem) -> list[ir.Constraint]:
    """What the scenario's constraints allow: not the readings of open starts the witness
    keeps to while they hold (``ir.Constraint.tentative``)."""
    return [c for c in active_constraints(problem, SolverOutcome("sat")) if not c.tentative]


def domains(problem: ConstraintProblem) -> dict[str, Domain]:
    """Every variable's :class:`Domain` (see the module docstring)."""
    active = _active(problem)
    found = bounds(active)
    sets: dict[str, set[Fraction | bool]] = {}
    conjuncts: list[ir.Term] = []
    for c in active:
        propagate.split_conjuncts(c.term, conjuncts)
    for term in conjuncts:
        atom = propagate.atom_of(term)
        if atom.kind == "set" and len(atom.names) == 1:
            name = atom.names[0]
            sets[name] = set(atom.values) & sets[name] if name in sets else set(atom.values)
    result: dict[str, Domain] = {}
    for name, var in problem.variables.items():
        low, high = found.get(name, (None, None))
        values: list[Fraction | bool] | None = None
        if var.sort == "bool":
            values = [False, True]
        elif name in sets:
            values = sorted(v for v in sets[name] if not isinstance(v, bool))
        elif var.enum:
            values = sorted({Fraction(v) for _, v in var.enum})
        elif var.sort == "int" and low is not None and high is not None:
            if high - low < MAX_VALUES:
                values = [Fraction(k) for k in range(_ceil(low), _floor(high) + 1)]
        if values is not None and var.sort != "bool":
            values = [
                v for v in values if (low is None or v >= low) and (high is None or v <= high)
            ]
        result[name] = Domain(low, high, tuple(values) if values is not None else None)
    return result


def _ceil(x: Fraction) -> int:
    return -((-x.numerator) // x.denominator)


def _floor(x: Fraction) -> int:
    return x.numerator // x.denominator


def equations(problem: ConstraintProblem) -> list[frozenset[str]]:
    """The unknowns of each equation that relates two or more of them, the constants
    (values that equations fix from constants alone) folded in."""
    active = _active(problem)
    fixed = propagate.determined([c.term for c in active])
    found: list[frozenset[str]] = []
    for c in active:
        conjuncts: list[ir.Term] = []
        propagate.split_conjuncts(propagate.fold(c.term, fixed), conjuncts)
        for term in conjuncts:
            if isinstance(term, ir.Op) and term.op == "==":
                names = frozenset(ir.names(term))
                if len(names) > 1 and names not in found:
                    found.append(names)
    return found
