"""The variables and constraints of one scenario's timing model, as ``verify.timing``
builds them and before they join the scenario's problem.

Every variable is named under :data:`TIMING_PREFIX` (never a parameter's name, never
shown in a witness). A time is a variable when it is more than a constant or another
variable, defined by a ``definition`` constraint, so that terms stay small however often
the time is used. An unknown (when a goal is reached, when an event occurs, which
``one_of`` member runs) is a free variable with a canonical first choice (zero times, the
first member): :meth:`TimingModel.holds_canonically` tells whether every constraint holds
at those choices, in which case the solver need not see the model. What the scenario
writes (a duration, an overlap, an event's time) is tracked as a ``timing`` constraint
of its own line, so that a conflict names the lines.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.source import Span
from osc2check.verify import ir, propagate
from osc2check.verify.timeline import (
    FALSE,
    NEVER,
    Time,
    all_of,
    compare,
    holds_as,
    implies,
)

__all__ = ["TIMING_PREFIX", "TimingModel", "is_timing_variable"]

#: the names of the timing model's variables begin with this (never a parameter's)
TIMING_PREFIX = "time:"
TIMING = "timing"  # the kind of a constraint of a written duration, overlap or event
DEFINITION = "definition"  # the kind of a rule that only defines a start or an end


def is_timing_variable(name: str) -> bool:
    """Whether ``name`` is a variable of the timing model (not shown in a witness)."""
    return name.startswith(TIMING_PREFIX)


@dataclass
class TimingModel:
    """The variables and constraints of one scenario's timing, before they join its problem.
    With ``symbolic`` every written value is tracked, else only what does not hold
    already."""

    symbolic: bool
    variables: dict[str, ir.Var] = field(default_factory=dict)
    definitions: list[ir.Constraint] = field(default_factory=list)
    tracked: list[ir.Constraint] = field(default_factory=list)
    defined: dict[str, ir.Term] = field(default_factory=dict)  # variable -> its value
    canonical: dict[str, ir.Term] = field(default_factory=dict)  # an unknown's first choice
    #: a written duration or event time -> the term of its value (symbolic models)
    written: dict[str, ir.Term] = field(default_factory=dict)

    def mark(self) -> tuple[int, int, int, int]:
        """What the model holds now, for :meth:`undo`."""
        return (len(self.variables), len(self.definitions), len(self.tracked), len(self.written))

    def undo(self, mark: tuple[int, int, int, int]) -> None:
        """Forget what was added since ``mark`` (a part of the model built again)."""
        n_vars, n_defs, n_tracked, n_written = mark
        for name in list(self.variables)[n_vars:]:
            del self.variables[name]
            self.defined.pop(name, None)
            self.canonical.pop(name, None)
        del self.definitions[n_defs:]
        del self.tracked[n_tracked:]
        for name in list(self.written)[n_written:]:
            del self.written[name]

    # ---- variables

    def var(self, name: str, sort: str) -> ir.Var:
        """A new variable named ``name`` under the prefix (numbered when the name is taken)."""
        full = f"{TIMING_PREFIX}{name}"
        unique, n = full, 1
        while unique in self.variables:
            n += 1
            unique = f"{full}#{n}"
        var = ir.Var(unique, sort, unit="s" if sort == "real" else "")
        self.variables[unique] = var
        return var

    def define(self, name: str, sort: str, term: ir.Term, span: Span) -> ir.Term:
        """``term`` itself when it is a constant or a variable, else a variable defined as
        it (so that terms stay small however often a time is used)."""
        if isinstance(term, (ir.Const, ir.Ref)):
            return term
        var = self.var(name, sort)
        self.defined[var.name] = term
        self.definitions.append(
            ir.Constraint(ir.op("==", ir.Ref(var), term), span, DEFINITION, var.name)
        )
        return ir.Ref(var)

    def bind(self, t: Time, name: str, span: Span) -> Time:
        """``t`` with its parts defined as variables (see :meth:`define`)."""
        return Time(
            self.define(f"{name}.ends", "bool", t.finite, span),
            self.define(f"{name}.at", "real", t.at, span),
        )

    def unknown(self, name: str, sort: str, span: Span, canonical: ir.Term) -> ir.Term:
        """A free variable whose first choice is ``canonical``."""
        var = self.var(name, sort)
        self.canonical[var.name] = canonical
        return ir.Ref(var)

    def rule(self, term: ir.Term, span: Span, text: str) -> None:
        """Add ``term`` as a ``definition`` constraint (never part of a conflict)."""
        if not holds_as(term, True):
            self.definitions.append(ir.Constraint(term, span, DEFINITION, text))

    def after(self, start: Time, name: str, span: Span, may_never: bool = False) -> Time:
        """An unknown time at or after ``start`` (``may_never``: or never)."""
        if start.never:
            return NEVER
        at = self.unknown(f"{name}.at", "real", span, start.at)
        self.rule(implies(start.finite, compare(">=", at, start.at)), span, f"{name} ends later")
        finite = start.finite
        if may_never:
            finite = all_of(finite, self.unknown(f"{name}.ends", "bool", span, FALSE))
        return Time(finite, at)

    def track(self, term: ir.Term, span: Span, text: str) -> None:
        """Add ``term``, what the line at ``span`` requires, as a ``timing`` constraint."""
        if self.symbolic or not holds_as(term, True):
            self.tracked.append(ir.Constraint(term, span, TIMING, text))

    # ---- the canonical choice

    def holds_canonically(self) -> bool:
        """Whether every constraint holds with each unknown at its first choice (zero
        times, the first member): then the timing can be kept, and the solver need not
        see it."""
        values: dict[str, Fraction | bool] = {}
        try:
            for name in self.variables:
                term = self.defined.get(name, self.canonical.get(name))
                if term is None:
                    return False
                value = propagate.evaluate(term, values)
                values[name] = value if isinstance(value, bool) else Fraction(value)
            return all(
                propagate.evaluate(c.term, values) is True
                for c in (*self.definitions, *self.tracked)
            )
        except (KeyError, TypeError, ZeroDivisionError):
            return False
