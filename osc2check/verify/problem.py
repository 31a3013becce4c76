"""The constraint problem of one scenario: its variables and constraints (``ir``),
what could not be encoded, and what the witness needs beside them (the start
placement, the timing model, preferred values, list items).

``pipeline.py`` builds it from the model; ``z3_backend.py`` solves it.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import TYPE_CHECKING, Unpack

from osc2check.source import Span
from osc2check.verify.ir import Constraint, ListItem, Skipped, Var, VarDetails, fits, guarded

if TYPE_CHECKING:
    from osc2check.verify.schedule import TimingPlan
    from osc2check.verify.starts import StartPlacement


@dataclass
class ConstraintProblem:
    """Everything the solver needs for one scenario instance."""

    scenario: str
    span: Span
    variables: dict[str, Var] = field(default_factory=dict)
    constraints: list[Constraint] = field(default_factory=list)
    removed_defaults: set[str] = field(default_factory=set)  # parameters after remove_default
    skipped: list[Skipped] = field(default_factory=list)  # written, but not encoded
    strings: dict[int, str] = field(default_factory=dict)  # string constants by their number
    placement: StartPlacement | None = None  # when the scenario has actors
    # plausible values where the constraints leave a choice: the witness draws there
    # when it can (``placement._preferences``); never a constraint
    preferred: dict[str, tuple[Fraction, Fraction]] = field(default_factory=dict)
    # list members of struct parameters given by a list literal (``keep(it.points ==
    # [p1, p2])``): their items, each a struct parameter's path or a constant
    # (``osc2check.verify.structs``)
    lists: dict[str, tuple[ListItem, ...]] = field(default_factory=dict)
    # the timing model, kept for the schedule of each run (``verify.schedule``); never a
    # constraint (``verify.timing`` adds those it needs)
    timing: TimingPlan | None = None
    # what the witness says of the problem beside its values: the readings of open starts
    # that gave way (``firm``)
    notes: list[str] = field(default_factory=list)

    def var(self, name: str, sort: str, span: Span | None = None, **kw: Unpack[VarDetails]) -> Var:
        existing = self.variables.get(name)
        if existing is None:
            existing = self.variables[name] = Var(name, sort, span=span, **kw)
        return existing

    def tentative_from(self, index: int, reading: str) -> None:
        """Make the constraints added since ``index`` tentative, of the reading that
        ``reading`` says (``ir.Constraint.tentative``)."""
        self.constraints[index:] = [replace(c, tentative=reading) for c in self.constraints[index:]]

    def firm(self, readings: Collection[str]) -> ConstraintProblem | None:
        """This problem without the tentative constraints of ``readings``, the witness
        saying that those readings gave way; None when it has none of them."""
        drop = [r for r in dict.fromkeys(c.tentative for c in self.constraints) if r in readings]
        if not drop:
            return None
        kept = [c for c in self.constraints if c.tentative not in drop]
        gave_way = [f"{reading}: that cannot hold here" for reading in drop]
        return replace(self, constraints=kept, notes=[*self.notes, *gave_way])

    def skip(self, span: Span, text: str, reason: str) -> None:
        """Record a constraint that cannot be encoded (it is reported, never dropped);
        once, however many passes meet it."""
        if not any(s.span == span and s.reason == reason for s in self.skipped):
            self.skipped.append(Skipped(span, text, reason))

    def add(self, constraint: Constraint) -> None:
        """Add ``constraint``, made false where it would divide by zero (``guarded``);
        one whose exact numbers could grow past ``numbers.MAX_VALUE_BITS`` is skipped
        (reported, C411) before anything computes them."""
        if not fits(constraint.term):
            reason = "it computes numbers too large to compute exactly, or out of range"
            self.skip(constraint.span, constraint.text, reason)
            return
        term = guarded(constraint.term)
        if term is not constraint.term:
            constraint = replace(constraint, term=term)
        self.constraints.append(constraint)
