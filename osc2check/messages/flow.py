"""The messages of the B codes (behaviour flow): waits that never end, empty
compositions, constant conditions, movements that run in parallel, recursion."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Related
from osc2check.messages.parts import diagnostic
from osc2check.source import Span

if TYPE_CHECKING:
    pass


def wait_without_emitter(span: Span, event: str) -> Diagnostic:
    return diagnostic(
        codes.WAIT_WITHOUT_EMITTER,
        f"nothing emits `{event}`, so this `wait` never ends; add `emit {event}` or "
        f"declare `event {event} is <condition>`",
        span,
    )


def wait_blocks_emitter(span: Span, event: str, emit_span: Span) -> Diagnostic:
    return diagnostic(
        codes.WAIT_BLOCKS_EMITTER,
        f"this `wait` for `{event}` comes before its only `emit` in the same serial "
        "chain, so neither ever happens",
        span,
        [Related(emit_span, f"`{event}` is emitted only here, after the wait")],
    )


def negative_duration(span: Span, text: str) -> Diagnostic:
    return diagnostic(codes.NEGATIVE_DURATION, f"duration `{text}` is negative", span)


def empty_one_of(span: Span) -> Diagnostic:
    return diagnostic(codes.EMPTY_ONE_OF, "`one_of` has no members to choose from", span)


def empty_composition(span: Span, op: str) -> Diagnostic:
    return diagnostic(codes.EMPTY_COMPOSITION, f"`{op}` has no members; it ends at once", span)


def constant_condition(span: Span, value: bool, what: str) -> Diagnostic:
    effect = "is always true" if value else "is never true"
    return diagnostic(codes.CONSTANT_CONDITION, f"this {what} {effect}", span)


def parallel_movements(span: Span, actor: str, other: Span) -> Diagnostic:
    return diagnostic(
        codes.PARALLEL_MOVEMENTS,
        f"`{actor}` gets two movement actions at the same time in this `parallel`",
        span,
        [Related(other, "the other movement action")],
    )


def recursive_scenario(span: Span, chain: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.RECURSIVE_SCENARIO,
        "scenario invokes itself: " + " -> ".join(f"`{n}`" for n in chain),
        span,
    )
