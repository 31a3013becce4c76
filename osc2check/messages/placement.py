"""The messages of the L codes (initial placement): actors that cannot be placed, unsafe
gaps, maps that cannot be read or found."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic
from osc2check.messages.parts import (
    diagnostic,
    quote_list,
)
from osc2check.source import Span

if TYPE_CHECKING:
    pass


def reference_not_placed(span: Span, actor: str, reference: str) -> Diagnostic:
    return diagnostic(
        codes.REFERENCE_NOT_PLACED,
        f"`{actor}` is placed relative to `{reference}`, which is not an actor of "
        "this scenario at the start",
        span,
    )


def cyclic_placement(span: Span, cycle: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.CYCLIC_PLACEMENT,
        "actors are placed relative to each other in a cycle: "
        + " -> ".join(f"`{a}`" for a in cycle)
        + "; runners that place actors one after the other cannot do this",
        span,
    )


def unsafe_gap(span: Span, text: str, follower: str, leader: str, min_gap: Fraction) -> Diagnostic:
    return diagnostic(
        codes.UNSAFE_GAP,
        f"`{text}` leaves `{follower}` less than {float(min_gap):g} s behind `{leader}` "
        f"at its start speed, whatever values the other constraints allow",
        span,
    )


def person_faster_than_walking(span: Span, text: str, person: str, limit: Fraction) -> Diagnostic:
    return diagnostic(
        codes.PERSON_FASTER_THAN_WALKING,
        f"`{text}` asks `{person}` to move faster than {float(limit):g} m/s "
        f"({float(limit) * 3.6:g} kph), faster than an adult walks, whatever values the "
        "other constraints allow",
        span,
    )


def unplaced_actor(span: Span, actor: str) -> Diagnostic:
    return diagnostic(
        codes.UNPLACED_ACTOR,
        f"nothing that begins at time 0 places `{actor}`; the solver picks its start "
        "(see `--witness`)",
        span,
    )


def unreadable_map(span: Span, name: str, problem: str, where: str | None) -> Diagnostic:
    at = f" (at {where})" if where else ""
    return diagnostic(
        codes.UNREADABLE_MAP,
        f"map `{name}` cannot be read: {problem}{at}; the actors are placed on the default "
        "road instead",
        span,
    )


def unknown_map(span: Span, name: str, known: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_MAP,
        f"unknown map `{name}`; the built-in maps are {quote_list(known, 10, 'and')}",
        span,
    )


def no_junction_ahead(span: Span, map_name: str) -> Diagnostic:
    """CARLA's ``path_over_junction`` on a map whose roads lead into no junction."""
    return diagnostic(
        codes.INFEASIBLE_PLACEMENT,
        f"no road of map `{map_name}` leads into a junction: the actors cannot start before "
        "one, as `path_over_junction` asks (CARLA's Town03 stand-in has one)",
        span,
    )
