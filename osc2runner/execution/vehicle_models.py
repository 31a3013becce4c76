"""Which model moves each vehicle of a run: the multibody model, or the kinematic one
for the vehicles the run's ``kinematic`` option selects (``sim/kinematic_bank.py``).

The option is a list of actor names and shell-style patterns (``npc*``, ``*``,
``v[0-9]``). A pattern selects the vehicles it matches that may run on the kinematic
model; a name must be such a vehicle. A vehicle may not when:

* the system under test drives it (its plant is the multibody model);
* it has a hitch receiver and the scenario has a trailer (only the multibody model
  tows, and a trailer may be hitched to it at any time).

Anything else the option names is an error before the first tick: a name that is
not a vehicle of the scenario, a pattern that selects no vehicle (a misspelt one would
otherwise change nothing without a word). ``*`` alone, "every vehicle that may", may
select none: a scenario without such vehicles runs as it is.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from fnmatch import fnmatchcase

from osc2runner.sim.state import ActorSpec
from osc2runner.sim.vehicle import VehicleParams

__all__ = ["kinematic_specs"]

_WILDCARDS = frozenset("*?[")


def _why_not(spec: ActorSpec, sut_actor: str | None, trailers: bool) -> str | None:
    """Why vehicle ``spec`` cannot run on the kinematic model, or None."""
    if spec.name == sut_actor:
        return f"`{spec.name}` is driven by the system under test (the multibody model)"
    if trailers and isinstance(spec.params, VehicleParams) and spec.params.can_tow:
        return f"`{spec.name}` may tow a trailer of this scenario (only the multibody model tows)"
    return None


def kinematic_specs(
    specs: Sequence[ActorSpec], selected: Sequence[str], sut_actor: str | None
) -> tuple[list[ActorSpec], list[str]]:
    """``specs`` with the vehicles ``selected`` names and patterns choose made kinematic,
    and what is wrong with the selection (each a sentence; none: the specs are good)."""
    if not selected:
        return list(specs), []
    vehicles = [spec for spec in specs if spec.kind == "vehicle"]
    trailers = any(spec.kind == "trailer" for spec in specs)
    kinds = {spec.name: spec.kind for spec in specs}
    chosen: set[str] = set()
    problems: list[str] = []
    for item in selected:
        if _WILDCARDS.isdisjoint(item):  # a name
            if kinds.get(item) != "vehicle":
                what = f"a {kinds[item]}" if item in kinds else "no actor of the scenario"
                problems.append(f"`{item}` is {what}: only vehicles run on the kinematic model")
                continue
            spec = next(v for v in vehicles if v.name == item)
            why = _why_not(spec, sut_actor, trailers)
            if why is not None:
                problems.append(why)
            else:
                chosen.add(item)
            continue
        matched = [v for v in vehicles if fnmatchcase(v.name, item)]
        able = [v.name for v in matched if _why_not(v, sut_actor, trailers) is None]
        if not able and item != "*":
            vehicles_named = ", ".join(f"`{v.name}`" for v in vehicles) or "none"
            problems.append(
                f"`{item}` selects no vehicle that can run on the kinematic model "
                f"(the scenario's vehicles: {vehicles_named})"
            )
        chosen.update(able)
    made = [replace(spec, kinematic=True) if spec.name in chosen else spec for spec in specs]
    return made, problems
