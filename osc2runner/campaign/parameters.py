"""Which of a campaign's parameters it sweeps, and what their constraints allow.

A campaign's runs differ in the scenario's parameters that constraints leave
open. Some of them the campaign *sweeps* (``ego_speed`` in [30..80] kph); others
*follow* from those (``gap == (ego_speed - target_speed) * ttc0``: the gap is
no parameter of its own). Every table, plot and name of the campaign shows the
swept ones, each of them (:func:`choose_axes`):

1. The parameters whose value differs between the finished runs are taken in
   order: the ``cover`` items' first, then those a constraint of their own bounds
   (a range, a set), then the others; among equals, the one with more distinct
   values first, then by name.
2. One *follows* from those taken before it when an equation relates it to them
   alone (:func:`osc2check.verify.domains.equations`), or when the runs show it as
   a function of one of them that repeats values (``gvt_offset`` of ``overlap``,
   which only implications relate); a function of a parameter whose every run has
   a value of its own is no evidence, so two continuous parameters both stay.
3. The others are swept.

The constraints' domain of each parameter (:func:`parameter_domains`: bounds and
allowed values in the unit the witness shows) is what the spread of the runs is
measured against (:mod:`osc2runner.campaign.spread`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from osc2check.verify import ir
from osc2check.verify.domains import domains, equations
from osc2runner.campaign.steering import scenario_result
from osc2runner.campaign.worker import RunRecord
from osc2runner.runner import Checked

__all__ = [
    "Axes",
    "choose_axes",
    "compact_text",
    "numeric",
    "parameter_domains",
    "parameter_equations",
]


def _shown(var: ir.Var, value: Fraction | bool) -> float | int | bool | str:
    """An SI value in the unit the witness shows (an enum member by name)."""
    if isinstance(value, bool):
        return value
    if var.enum:
        return next((n for n, v in var.enum if v == value), str(value))
    shown = (value - var.unit_offset) / var.unit_factor
    return int(shown) if var.sort == "int" else float(shown)


def parameter_domains(checked: Checked) -> dict[str, dict[str, Any]]:
    """Per scenario parameter (not the actors' starts): its ``unit``, ``sort`` (``real``,
    ``int``, ``enum``, ``bool``, ``string``), ``low`` and ``high`` (None: unbounded)
    and ``values`` (the allowed ones, or None when they are not few), in the unit the
    witness shows."""
    problem = scenario_result(checked).problem
    found: dict[str, dict[str, Any]] = {}
    for name, domain in domains(problem).items():
        if "@" in name:
            continue
        var = problem.variables[name]
        sort = "enum" if var.enum else "string" if var.is_string else var.sort
        found[name] = {
            "unit": var.unit,
            "sort": sort,
            "low": _shown(var, domain.low) if domain.low is not None and not var.enum else None,
            "high": _shown(var, domain.high) if domain.high is not None and not var.enum else None,
            "values": [_shown(var, v) for v in domain.values] if domain.values else None,
        }
    return found


def parameter_equations(checked: Checked) -> list[list[str]]:
    """The scenario parameters each equation relates (those between parameters alone)."""
    problem = scenario_result(checked).problem
    return [sorted(names) for names in equations(problem) if not any("@" in n for n in names)]


@dataclass
class Axes:
    """The swept parameters in order, and each varying one that follows, with why."""

    swept: list[str] = field(default_factory=list)
    derived: dict[str, str] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return {"swept": self.swept, "derived": self.derived}


def _value(r: RunRecord, name: str) -> Any:
    return r.parameters.get(name, {}).get("value")


def _function_of(given: list[str], other: list[str]) -> bool:
    """Whether ``other`` is the same wherever ``given`` is, with some value of ``given``
    repeated (evidence, not a coincidence of distinct values)."""
    seen: dict[str, str] = {}
    for a, b in zip(given, other, strict=True):
        if seen.setdefault(a, b) != b:
            return False
    return len(seen) < len(given)


def choose_axes(
    records: Sequence[RunRecord],
    domains: Mapping[str, Mapping[str, Any]],
    equations: Sequence[Sequence[str]],
    preferred: Sequence[str] = (),
) -> Axes:
    """The swept and the derived parameters of the finished ``records`` (see the module
    docstring); ``preferred`` are the cover items' names."""
    done = [r for r in records if r.finished]
    values = {
        name: [str(_value(r, name)) for r in done]
        for name in sorted({n for r in done for n in r.parameters})
    }
    varying = [n for n, v in values.items() if len(set(v)) > 1]

    def bounded(name: str) -> bool:
        d = domains.get(name, {})
        return bool(d.get("values")) or d.get("low") is not None or d.get("high") is not None

    order = sorted(
        varying,
        key=lambda n: (n not in preferred, not bounded(n), -len(set(values[n])), n),
    )
    axes = Axes()
    for name in order:
        related = next(
            (e for e in equations if name in e and set(e) - {name} <= set(axes.swept)), None
        )
        if related is not None:
            others = ", ".join(f"`{n}`" for n in related if n != name)
            axes.derived[name] = f"follows from {others} by an equation"
            continue
        source = next((c for c in axes.swept if _function_of(values[c], values[name])), None)
        if source is not None:
            axes.derived[name] = f"follows from `{source}` in every run"
            continue
        axes.swept.append(name)
    return axes


def numeric(value: Any) -> float | None:
    """A finite number (not a bool), else None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def compact_text(value: Any, unit: str) -> str:
    """A parameter's value for a name: ``75.8kph``, ``-0.08m``, ``car``, ``true``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    number = numeric(value)
    if number is None:
        return str(value)
    return f"{number:.3g}{unit}" if abs(number) < 1000 else f"{number:.0f}{unit}"
