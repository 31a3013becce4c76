"""Parameter values and start poses from the checker's witness (``osc2check.solve``).

:class:`WitnessValues` implements :class:`~osc2runner.values.ParameterValues`
over a :class:`osc2check.verify.witness.Witness`: the solver's exact value of
every parameter (seeded), and every actor's start lane, position, heading and
speed, which the initializer then realises as they are. Values the witness
does not name fall back to the folded constants.

Actor attributes are taken from the witness only when a constraint mentions
them (``keep(it.model == ...)``): a vehicle whose category nothing constrains
stays a car rather than whatever the solver happened to pick.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2runner.errors import Problem, ScenarioError
from osc2runner.values import ConstantValues, EnumValue, ParameterValues, Quantity, to_json

__all__ = ["WitnessStart", "WitnessValues", "witness_values"]


@dataclass(frozen=True, slots=True)
class WitnessStart:
    """One actor's start as the witness gives it (lane in the scenario's numbering)."""

    lane: int
    s: float
    t: float
    heading: float
    speed: float


def _exact(value: object, type_: T.Type | None) -> object:
    if isinstance(value, bool) or type_ is None:
        return value
    if type_.kind is T.Kind.PHYSICAL and isinstance(value, Fraction):
        return Quantity(value, type_.dimension or T.DIMENSIONLESS)
    if type_.kind in (T.Kind.INT, T.Kind.UINT) and isinstance(value, Fraction):
        return int(value)
    if type_.kind is T.Kind.ENUM and isinstance(value, str):
        return EnumValue(type_.symbol.name if type_.symbol is not None else "", value)
    return value


class WitnessValues(ParameterValues):
    """The values of one witness, with the folded constants as a fallback."""

    def __init__(self, model: Model, scenario: Symbol, witness: Any) -> None:
        self.model = model
        self.scenario = scenario
        self.witness = witness
        self.fallback = ConstantValues(model, scenario)
        self._by_name = {p.name: p for p in witness.parameters}

    def value(self, field: Symbol) -> object:
        p = self._by_name.get(field.name)
        if p is None:
            return self.fallback.value(field)
        return _exact(p.value, field.type)

    def attribute(self, actor: Symbol, member: str) -> object | None:
        p = self._by_name.get(f"{actor.name}.{member}")
        if p is None or not p.constrained:
            return self.fallback.attribute(actor, member)
        owner = actor.type.symbol if actor.type is not None else None
        found = self.model.member(owner, member) if owner is not None else []
        return _exact(p.value, found[0].type if found else None)

    def attributes(self, actor: Symbol) -> dict[str, object]:
        result = dict(self.fallback.attributes(actor))
        prefix = f"{actor.name}."
        for name, p in self._by_name.items():
            rest = name[len(prefix) :] if name.startswith(prefix) else ""
            if rest and p.constrained and "@" not in rest and "." not in rest:
                value = self.attribute(actor, rest)
                if value is not None:
                    result[rest] = value
        return result

    def start(self, name: str) -> WitnessStart | None:
        """The witness's start of actor ``name``, or None."""
        a = self.witness.actor(name)
        if a is None:
            return None
        return WitnessStart(int(a.lane), float(a.s), float(a.t), float(a.heading), float(a.speed))

    def table(self) -> dict[str, object]:
        result = self.fallback.table()
        for p in self.witness.parameters:
            if p.constrained and "@" not in p.name and "." not in p.name:
                sym = next((f for f in self.fallback.fields if f.name == p.name), None)
                result[p.name] = to_json(_exact(p.value, sym.type if sym else None))
        return result

    @property
    def source(self) -> str:
        return f"witness (seed {self.witness.seed})"


def witness_values(seed: int = 0) -> Callable[..., ParameterValues]:
    """A values factory for :func:`osc2runner.run` that solves for the witness.

    An unsatisfiable scenario is an input error (the checker's diagnostics are
    reported); when the solver gives no answer the constants are used.
    """

    def factory(analysis: Any, uri: str, model: Model, scenario: Symbol) -> ParameterValues:
        from osc2check.verify.api import Unsolvable, solve

        result = solve(analysis, scenario=scenario.name, seed=seed, uri=uri)
        if isinstance(result, Unsolvable):
            if result.status == "unsat":
                raise ScenarioError(
                    [Problem(f"scenario `{scenario.name}` has no solution")],
                    diagnostics=result.diagnostics,
                    texts=analysis.texts,
                )
            values = ConstantValues(model, scenario)
            return values
        return WitnessValues(model, scenario, result)

    return factory
