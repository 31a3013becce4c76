"""Traffic lights: the scenario's ``traffic_light`` parameters, placed and switchable.

In the standard a traffic light is a struct (``traffic_light``: a ``pose``, a
size, a ``group`` and its ``bulbs``), switched by the actions of a
``traffic_light_controller``. Every scenario parameter of that type is a light
in the world, at the world ``x``, ``y`` and yaw of its ``pose`` (the witness's
values) — or, when its ``map_id`` names a dynamic ``<signal>`` of the map, at
that signal (its pose from the signal's road, ``s``, ``t``, orientation and
``hOffset``, facing the traffic it is valid for; the ``pose`` is then not
read). A light whose ``map_id`` the map does not have (a built-in map has no
signals) is the scenario's own and stands at its ``pose`` when the scenario
gives the pose's ``x`` and ``y``; without them it stops the run before it
starts, with the ids the map has. A light on the map without a ``group.map_id``
is in the group of the map's ``<controller>`` that lists its signal. Its bulbs
are the ``bulbs`` the scenario lists (``keep(it.bulbs == [red_bulb, ...])``),
else a three-bulb head of red, yellow and green circles. Every bulb starts
``is_off`` (the light's semantic state is ``off``) until an action switches it.

The light's value is one object for the whole run: an expression that reads
``tl.bulbs[0].state`` reads the state of the moment. Lights of the same group
are those whose ``group.map_id`` is equal. Each light keeps the ticks at which
its state changed (:attr:`TrafficLight.history`), from which the telemetry's
``lights.csv`` is written: nothing is done per tick for a light that does not
change.

Semantic states and the bulbs they light (the European three-bulb head; the
standard names the states, not the bulbs):

================== =============================================
``off``            every bulb off
``stop``           red on
``stop_attention`` red and yellow on (about to go)
``attention``      yellow on (about to stop)
``caution``        yellow flashing
``go``             green on
``go_exclusive``   green on (a protected movement)
``non_functional`` yellow flashing
================== =============================================
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

from osc2check.semantics.constants import NotConstant
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.world.network import RoadNetwork
from osc2runner.errors import RunProblem
from osc2runner.instance.values import ScenarioValues, scenario_fields
from osc2runner.structs import StructValue, as_pose

__all__ = ["SEMANTIC_BULBS", "LightState", "TrafficLight", "semantic_of", "traffic_lights"]

#: the bulbs (colour -> state) each semantic state lights; the others are off
SEMANTIC_BULBS: dict[str, dict[str, str]] = {
    "off": {},
    "stop": {"red": "is_on"},
    "stop_attention": {"red": "is_on", "yellow": "is_on"},
    "attention": {"yellow": "is_on"},
    "caution": {"yellow": "is_flashing"},
    "go": {"green": "is_on"},
    "go_exclusive": {"green": "is_on"},
    "non_functional": {"yellow": "is_flashing"},
}
_DEFAULT_HEAD = ("red", "yellow", "green")


@dataclass(frozen=True, slots=True)
class LightState:
    """What a light shows from ``tick`` on: its semantic state and each bulb's
    ``(colour, icon, state)``."""

    tick: int
    semantic: str
    bulbs: tuple[tuple[str, str, str], ...]


@dataclass
class TrafficLight:
    """One light in the world: its name (the parameter's), pose and value (live bulbs),
    and its states since the start (one entry per change, the first at tick 0)."""

    name: str
    x: float
    y: float
    yaw: float
    value: StructValue
    history: list[LightState] = dataclasses.field(default_factory=list)
    controller: str = ""  # the map's <controller> that switches it, for a light on the map
    placed: str = "pose"  # where it stands: at its "pose", or at the map's "signal"

    def __post_init__(self) -> None:
        if not self.history:
            self.changed(0)

    def changed(self, tick: int) -> None:
        """Note the state it shows from ``tick`` on (the last change in a tick wins)."""
        state = LightState(
            tick,
            self.semantic(),
            tuple((str(b.color), str(b.icon), str(b.state)) for b in self.bulbs),
        )
        if self.history and self.history[-1].tick == tick:
            self.history[-1] = state
        else:
            self.history.append(state)

    @property
    def bulbs(self) -> tuple[StructValue, ...]:
        return bulbs_of(self.value)

    @property
    def group(self) -> str:
        group = getattr(self.value, "group", None)
        named = str(getattr(group, "map_id", "") or "") if group is not None else ""
        return named or self.controller

    def semantic(self) -> str:
        """The semantic state its bulbs express (``non_functional`` when none matches)."""
        return semantic_of(self.bulbs)

    def describe(self) -> str:
        lit = ", ".join(f"{b.color} {b.icon} {b.state}" for b in self.bulbs)
        return f"{self.semantic()} ({lit})"


def bulbs_of(light: StructValue) -> tuple[StructValue, ...]:
    """The bulbs of a ``traffic_light`` value (the witness's list, or the default head's)."""
    bulbs = light.fields.get("bulbs", ())
    assert isinstance(bulbs, tuple)
    return bulbs


def as_bulbs(value: object) -> tuple[StructValue, ...]:
    """A ``list of traffic_light_bulb`` value as its bulbs (none: empty)."""
    given = () if value is None else value
    bulbs = (
        tuple(b for b in given if isinstance(b, StructValue)) if isinstance(given, tuple) else ()
    )
    if bulbs != given:
        raise TypeError(f"`{value!r}` is not a list of traffic_light_bulb")
    return bulbs


def semantic_of(bulbs: Sequence[StructValue]) -> str:
    """The semantic state that bulbs in these states express."""
    lit = {str(b.color): str(b.state) for b in bulbs if str(b.state) not in ("is_off", "unknown")}
    for semantic, wanted in SEMANTIC_BULBS.items():
        if lit == wanted and semantic not in ("go_exclusive", "non_functional"):
            return semantic
    return "non_functional"


def traffic_lights(
    model: Model, scenario: Symbol, values: ScenarioValues, network: RoadNetwork
) -> tuple[list[TrafficLight], list[RunProblem]]:
    """The scenario's traffic lights (parameters of type ``traffic_light``), in order, and
    the problems of those that cannot be placed (a ``map_id`` the map does not have)."""
    found: list[TrafficLight] = []
    problems: list[RunProblem] = []
    on_map = {s.id: s for s in network.signals if s.dynamic}
    for field in scenario_fields(model, scenario):
        t = field.type
        if field.kind is not SymbolKind.FIELD or t is None or t.symbol is None:
            continue
        if not any(a.name == "traffic_light" for a in model.ancestors(t.symbol)):
            continue
        try:
            value = values.struct(field.name, field)
        except NotConstant:
            continue
        bulbs = value.fields.get("bulbs")
        if not bulbs:
            value.bulbs = tuple(
                StructValue(
                    "traffic_light_bulb",
                    {
                        "map_id": "",
                        "icon": "circle",
                        "color": color,
                        "icon_positive": True,
                        "state": "is_off",
                    },
                )
                for color in _DEFAULT_HEAD
            )
        else:
            for bulb in bulbs_of(value):
                bulb.state = "is_off"
        map_id = str(getattr(value, "map_id", "") or "")
        signal = on_map.get(map_id) if map_id else None
        posed = all(
            values.constrained_si(f"{field.name}.pose.position.{axis}") is not None
            for axis in ("x", "y")
        )
        if signal is not None:
            where = network.signal_pose(signal)
            x, y, yaw = where.x, where.y, where.yaw
            controller = next((c.id for c in network.controllers if map_id in c.signals), "")
            placed = "signal"
        elif map_id and not posed:
            have = ", ".join(sorted(on_map)) or "none"
            problems.append(
                RunProblem(
                    f"traffic light {field.name!r}: map_id {map_id!r} is not a traffic "
                    f"light of the map (its dynamic signals: {have}), and its pose is not "
                    "given (keep(it.pose.position.x == ...), .y) to stand it there instead",
                    field.name_span,
                )
            )
            continue
        else:
            controller = ""
            pose = as_pose(value.pose)
            x, y, yaw = pose.position.x, pose.position.y, pose.orientation.yaw
            placed = "pose"
        found.append(
            TrafficLight(field.name, x, y, yaw, value, controller=controller, placed=placed)
        )
    return found, problems
