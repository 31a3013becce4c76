"""Traffic-light control files (``map.set_traffic_lights_control_file(file)``, ASAM
OpenSCENARIO DSL 2.1 §8.12.2.2): the signal plans a scenario's lights run by.

The standard names the modifier, not the file's format. **Choice**: the format of
ASAM OpenSCENARIO XML 1.x for signal plans, the ``<TrafficSignals>`` element of a
``<RoadNetwork>`` (a whole ``.xosc`` file, or a file whose root is
``<TrafficSignals>``), as esmini and CARLA read it::

    <TrafficSignals>
      <TrafficSignalController name="ns" delay="0">
        <Phase name="go" duration="20">
          <TrafficSignalState trafficSignalId="tl2" state="go"/>
        </Phase>
        <Phase name="attention" duration="3">
          <TrafficSignalState trafficSignalId="tl2" state="off;on;off"/>
        </Phase>
        ...
      </TrafficSignalController>
    </TrafficSignals>

* A controller runs its phases in order, each for its ``duration`` (s), round and
  round, from the scenario's start plus its ``delay`` (plus, with ``reference``,
  the delay of the controller it names); before that its lights are as they are.
* ``trafficSignalId`` names a light of the scenario by its ``map_id``, else by its
  parameter name; ids that no light of the scenario has are not lights of the run
  (the standard makes a light a parameter) and are listed in ``run.json``'s notes.
* ``state`` is a semantic state (``stop``, ``go``, ``attention``, ...: the bulbs it
  lights, as the controller's actions light them) or one state per bulb of the
  light, in its bulbs' order, separated by ``;`` (``on``, ``off``, ``flashing``,
  or ``is_on``, ...: esmini's ``off;off;on``).
* The file is relative to the scenario file. A file that cannot be read, is not
  XML, has no controller, a phase without a positive duration or a state the light
  cannot show stops the run before it starts, naming the place in the file.

The plans are data here; ``behaviours.traffic.run_plans`` plays them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from osc2check.semantics.members import declaration_bodies, scenario_members
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.world.errors import MapError
from osc2check.world.opendrive.xmltree import Element, parse_xml
from osc2runner.errors import RunProblem
from osc2runner.instance.lights import SEMANTIC_BULBS, TrafficLight

__all__ = ["LightPlan", "PlanPhase", "control_plans"]

_BULB_STATES = {
    "on": "is_on",
    "off": "is_off",
    "flashing": "is_flashing",
    "is_on": "is_on",
    "is_off": "is_off",
    "is_flashing": "is_flashing",
}


@dataclass(frozen=True, slots=True)
class PlanPhase:
    """One phase: how long it lasts and each light's bulb states (in its bulbs' order)."""

    name: str
    duration: float
    states: tuple[tuple[TrafficLight, tuple[str, ...]], ...]


@dataclass(frozen=True, slots=True)
class LightPlan:
    """One controller of a control file: its phases and when it starts (s)."""

    name: str
    start: float
    phases: tuple[PlanPhase, ...]

    @property
    def period(self) -> float:
        return sum(p.duration for p in self.phases)


def control_plans(
    model: Model,
    scenario: Symbol,
    lights: list[TrafficLight],
    folder: Path,
) -> tuple[list[LightPlan], list[str], list[RunProblem]]:
    """The plans of the scenario's control files, the notes on ids that are no light of
    the run, and the problems (see the module docstring)."""
    plans: list[LightPlan] = []
    notes: list[str] = []
    problems: list[RunProblem] = []
    for name, node in _control_files(model, scenario):
        if name is None:
            problems.append(
                RunProblem("the control file must be given as a string literal", node.span)
            )
            continue
        path = Path(name) if Path(name).is_absolute() else folder / name
        try:
            try:
                data = path.read_bytes()
            except OSError as exc:
                raise MapError(
                    f"cannot read the control file: {exc.strerror or exc}", str(path)
                ) from None
            found, unknown = _plans(parse_xml(data, str(path)), lights)
        except MapError as exc:
            problems.append(RunProblem(f"traffic-light control file: {exc}", node.span))
            continue
        plans.extend(found)
        notes.extend(
            f"control file {name}: signal {signal!r} is not a traffic light of the scenario"
            for signal in unknown
        )
    return plans, notes, problems


def _control_files(model: Model, scenario: Symbol) -> list[tuple[str | None, ast.Node]]:
    """``(file, node)`` of every ``set_traffic_lights_control_file`` the scenario applies
    (``None`` when the file is not a string literal)."""
    found: list[tuple[str | None, ast.Node]] = []
    for member in scenario_members(model, declaration_bodies(model), scenario):
        if not isinstance(member, ast.Invocation):
            continue
        sym = model.references.get(member.name)
        if sym is None or sym.kind is not SymbolKind.MODIFIER:
            continue
        if sym.name != "set_traffic_lights_control_file":
            continue
        binding = model.binding(member)
        value = binding.value("file") if binding is not None else None
        if isinstance(value, ast.StringLiteral):
            found.append((value.value, value))
        else:
            found.append((None, value if value is not None else member))
    return found


def _signals(root: Element) -> Element:
    """The ``<TrafficSignals>`` element: the root, or inside an OpenSCENARIO document."""
    if root.tag == "TrafficSignals":
        return root
    stack = [root]
    while stack:
        element = stack.pop()
        if element.tag == "TrafficSignals":
            return element
        stack.extend(reversed(element.children))
    raise root.error("no <TrafficSignals> element (the OpenSCENARIO XML signal plans)")


def _plans(root: Element, lights: list[TrafficLight]) -> tuple[list[LightPlan], list[str]]:
    signals = _signals(root)
    controllers = signals.findall("TrafficSignalController")
    if not controllers:
        raise signals.error("<TrafficSignals> has no <TrafficSignalController>")
    by_id = {str(getattr(light.value, "map_id", "") or ""): light for light in lights}
    by_id.pop("", None)
    by_name = {light.name: light for light in lights}
    delays = {
        c.text("name", ""): (c.number("delay", 0.0), c.optional_text("reference"))
        for c in controllers
    }
    unknown: list[str] = []
    plans = []
    for controller in controllers:
        phases = []
        for phase in controller.findall("Phase"):
            duration = phase.number("duration")
            if duration <= 0.0:
                raise phase.error("<Phase> attribute `duration` must be more than 0 s")
            states = []
            for state in phase.findall("TrafficSignalState"):
                signal = state.text("trafficSignalId")
                light = by_id.get(signal) or by_name.get(signal)
                if light is None:
                    if signal not in unknown:
                        unknown.append(signal)
                    continue
                states.append((light, _bulbs(state, light)))
            phases.append(PlanPhase(phase.text("name", ""), duration, tuple(states)))
        if not phases:
            raise controller.error("<TrafficSignalController> has no <Phase>")
        name = controller.text("name", "")
        plans.append(LightPlan(name, _start(name, delays, controller), tuple(phases)))
    return plans, unknown


def _start(name: str, delays: dict[str, tuple[float, str | None]], controller: Element) -> float:
    """A controller's start: its delay, plus its reference's start (a cycle is an error)."""
    start, seen = 0.0, [name]
    current: str | None = name
    while current is not None:
        delay, reference = delays[current]
        start += delay
        if reference is not None and reference not in delays:
            raise controller.error(
                f"<TrafficSignalController> reference {reference!r} is no controller"
            )
        if reference in seen:
            raise controller.error("the controllers' references make a cycle")
        if reference is not None:
            seen.append(reference)
        current = reference
    return start


def _bulbs(state: Element, light: TrafficLight) -> tuple[str, ...]:
    """The bulb states a ``<TrafficSignalState>`` gives ``light``, in its bulbs' order."""
    text = state.text("state")
    wanted = SEMANTIC_BULBS.get(text)
    if wanted is not None:
        return tuple(wanted.get(str(b.color), "is_off") for b in light.bulbs)
    parts = [p.strip() for p in text.split(";")]
    if len(parts) != len(light.bulbs) or any(p not in _BULB_STATES for p in parts):
        raise state.error(
            f"state {text!r} is neither a semantic state ({', '.join(SEMANTIC_BULBS)}) nor "
            f"one of on, off, flashing for each of the {len(light.bulbs)} bulbs of "
            f"{light.name!r}, separated by ';'"
        )
    return tuple(_BULB_STATES[p] for p in parts)
