"""The messages of the C codes (constraints), and the one message of every conflict the
solver finds (``unsatisfiable``: C401, the L5xx conflicts of the start and B608)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.codes import Code
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.messages.parts import diagnostic
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.verify.ir import Constraint


def _member_notes(members: Iterable[Constraint]) -> list[Related]:
    """Related locations for the other members of a conflict, each with its source text."""
    notes = []
    for c in members:
        if c.kind in ("domain", "placement"):
            notes.append(Related(c.span, c.explanation or c.text))
        else:
            notes.append(Related(c.span, f"conflicts with `{c.text}`"))
    return notes


def unsatisfiable(
    code: Code, primary: Constraint, others: Sequence[Constraint], scenario: str
) -> Diagnostic:
    lead = {
        "C401": "constraints of scenario `{s}` cannot all hold",
        "L501": "the start positions of scenario `{s}` cannot all hold",
        "L502": "actors of scenario `{s}` would overlap at the start",
        "L503": "this puts an actor of scenario `{s}` in a lane the road does not have",
        "L507": "this puts an actor of scenario `{s}` off the road",
        "L508": "this speed in scenario `{s}` is above what the vehicle can reach",
        "L514": "the road is too short for what scenario `{s}` makes an actor do",
        "B608": "no run of scenario `{s}` can keep these durations",
    }[code.code].format(s=scenario)
    texts = [
        f"`{c.text}`" if c.kind not in ("domain", "placement") else (c.explanation or c.text)
        for c in (primary, *others)
    ]
    message = f"{lead}: " + "; ".join(texts)
    if any(c.strength == "default" for c in [primary, *others]):
        message += (
            "; a default yields only to `==` or `in` on the parameter alone, or to `remove_default`"
        )
    return diagnostic(code, message, primary.span, _member_notes(others))


def reversed_range(span: Span, low: str, high: str) -> Diagnostic:
    return diagnostic(
        codes.REVERSED_RANGE,
        f"the range is written from `{low}` down to `{high}`; OSC2 reads it as "
        f"`[{high}..{low}]`, write it that way",
        span,
        fix=Fix(f"write `[{high}..{low}]`", (TextEdit(span, f"[{high}..{low}]"),)),
    )


def default_overridden(default: Constraint, by: Constraint | None) -> Diagnostic:
    if by is None:
        return diagnostic(
            codes.DEFAULT_OVERRIDDEN,
            f"default `{default.text}` is removed by `remove_default`",
            default.span,
        )
    return diagnostic(
        codes.DEFAULT_OVERRIDDEN,
        f"default `{default.text}` is replaced by `{by.text}`",
        default.span,
        [Related(by.span, "the constraint that replaces it")],
    )


def conflicting_defaults(later: Constraint, earlier: Constraint) -> Diagnostic:
    return diagnostic(
        codes.CONFLICTING_DEFAULTS,
        f"`{later.text}` gives the parameter another default than `{earlier.text}`; "
        "the later one wins",
        later.span,
        [Related(earlier.span, "the earlier default")],
    )


def vacuous_constraint(constraint: Constraint) -> Diagnostic:
    return diagnostic(
        codes.VACUOUS_CONSTRAINT,
        f"`{constraint.text}` holds for every value its parameters can take; it constrains nothing",
        constraint.span,
    )


def solver_inconclusive(span: Span, scenario: str, reason: str) -> Diagnostic:
    return diagnostic(
        codes.SOLVER_INCONCLUSIVE,
        f"the solver could not decide whether the constraints of scenario `{scenario}` "
        f"can all hold ({reason}); raise `[tool.osc2check.solver] rlimit` to try "
        "harder",
        span,
    )


def scenario_budget(span: Span, scenario: str, limit: int) -> Diagnostic:
    return diagnostic(
        codes.SOLVER_INCONCLUSIVE,
        f"the constraints of scenario `{scenario}` are not checked: the solver checks the "
        f"first {limit} scenarios of a file; check it alone with `--scenario {scenario}`",
        span,
    )


def nonlinear_constraint(constraint: Constraint) -> Diagnostic:
    return diagnostic(
        codes.NONLINEAR_CONSTRAINT,
        f"`{constraint.text}` multiplies or divides unknowns; it is solved within the "
        "solver's budget and may be inconclusive",
        constraint.span,
    )


def unverified_constraint(
    span: Span, text: str, reason: str, written_at: Span | None = None
) -> Diagnostic:
    """C411 at ``span``; ``written_at`` is where the constraint is when that is elsewhere
    (another file: the finding is then at the scenario that uses it)."""
    related = [Related(written_at, f"`{text}` is written here")] if written_at else []
    return diagnostic(
        codes.UNVERIFIED_CONSTRAINT,
        f"`{text}` is not verified: {reason}; the verdict and the witness leave it out",
        span,
        related,
    )
