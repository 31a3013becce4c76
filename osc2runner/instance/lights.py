"""Traffic lights: the scenario's ``traffic_light`` parameters, placed and switchable.

In the standard a traffic light is a struct (``traffic_light``: a ``pose``, a
size, a ``group`` and its ``bulbs``), switched by the actions of a
``traffic_light_controller``. Every scenario parameter of that type is a light
in the world, at the world ``x``, ``y`` and yaw of its ``pose`` (the witness's
values). Its bulbs are the ``bulbs`` the scenario lists
(``keep(it.bulbs == [red_bulb, ...])``), else a three-bulb head of red, yellow
and green circles. Every bulb starts ``is_off`` (the light's semantic state is
``off``) until an action switches it.

The light's value is one object for the whole run: an expression that reads
``tl.bulbs[0].state`` reads the state of the moment. Lights of the same group
are those whose ``group.map_id`` is equal.

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

from dataclasses import dataclass
from types import SimpleNamespace

from osc2check.semantics.constants import NotConstant
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2runner.instance.values import ScenarioValues, scenario_fields

__all__ = ["SEMANTIC_BULBS", "TrafficLight", "semantic_of", "traffic_lights"]

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


@dataclass
class TrafficLight:
    """One light in the world: its name (the parameter's), pose and value (live bulbs)."""

    name: str
    x: float
    y: float
    yaw: float
    value: SimpleNamespace

    @property
    def bulbs(self) -> tuple[SimpleNamespace, ...]:
        return tuple(self.value.bulbs)

    @property
    def group(self) -> str:
        group = getattr(self.value, "group", None)
        return str(getattr(group, "map_id", "")) if group is not None else ""

    def semantic(self) -> str:
        """The semantic state its bulbs express (``non_functional`` when none matches)."""
        return semantic_of(self.bulbs)

    def describe(self) -> str:
        lit = ", ".join(f"{b.color} {b.icon} {b.state}" for b in self.bulbs)
        return f"{self.semantic()} ({lit})"


def semantic_of(bulbs: tuple[SimpleNamespace, ...] | list[SimpleNamespace]) -> str:
    """The semantic state that bulbs in these states express."""
    lit = {str(b.color): str(b.state) for b in bulbs if str(b.state) not in ("is_off", "unknown")}
    for semantic, wanted in SEMANTIC_BULBS.items():
        if lit == wanted and semantic not in ("go_exclusive", "non_functional"):
            return semantic
    return "non_functional"


def traffic_lights(model: Model, scenario: Symbol, values: ScenarioValues) -> list[TrafficLight]:
    """The scenario's traffic lights (parameters of type ``traffic_light``), in order."""
    found: list[TrafficLight] = []
    for field in scenario_fields(model, scenario):
        t = field.type
        if field.kind is not SymbolKind.FIELD or t is None or t.symbol is None:
            continue
        if not any(a.name == "traffic_light" for a in model.ancestors(t.symbol)):
            continue
        try:
            value = values.value(field)
        except NotConstant:
            continue
        assert isinstance(value, SimpleNamespace)
        bulbs = getattr(value, "bulbs", None)
        if not bulbs:
            value.bulbs = tuple(
                SimpleNamespace(
                    map_id="", icon="circle", color=color, icon_positive=True, state="is_off"
                )
                for color in _DEFAULT_HEAD
            )
        else:
            for bulb in bulbs:
                bulb.state = "is_off"
        pose = value.pose
        found.append(
            TrafficLight(
                field.name,
                float(pose.position.x),
                float(pose.position.y),
                float(pose.orientation.yaw),
                value,
            )
        )
    return found
