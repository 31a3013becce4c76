"""A concrete run written as ASAM OpenSCENARIO XML 1.2: a replay other players can run.

:func:`write_xosc` writes ``OUT.xosc`` and beside it ``OUT.xodr``, the road
network the run drove on: the OpenDRIVE file it used, copied, or the built-in
road written out (:mod:`.xodr`). The scenario names it by its file name
(``RoadNetwork/LogicFile``), so the two files travel together.

What is written (docs/export.md has the table of what carries over):

* **Entities**: one per actor, named as in the scenario. Vehicles and trailers
  are ``Vehicle`` (category from the catalogue's, bounding box, performance,
  axles; the reference point is the rear axle's centre, as OpenSCENARIO's vehicle
  coordinate system has it), persons and animals ``Pedestrian``, stationary
  objects ``MiscObject`` (obstacle), their reference point the box centre.
* **Init**: every actor's start pose (``TeleportAction``, ``WorldPosition``) and
  speed; the environment at the start; every traffic light's state at tick 0.
* **Trajectories**: each actor that can move follows a ``Polyline`` with one
  vertex per control tick (``FollowTrajectoryAction``, ``TimeReference/Timing``
  ``absolute``, scale 1, offset 0; ``followingMode="position"``): the player puts
  the actor where it was at each tick's time. Headings are unwrapped, so a
  player that interpolates between two vertices never turns the long way round.
* **Environment and lights**: each environment action (rain, snow, fog, wind,
  clouds, air, the sun, road friction) is an ``EnvironmentAction`` with the whole
  environment as it then was, and each change of a light a
  ``TrafficSignalStateAction`` (the signal id is the light's ``map_id`` on an
  OpenDRIVE map, else the name of the signal written for it), each at its
  simulation time.
* **Events**: each ``emit`` of the scenario is an ``Event`` named ``emit NAME #k``
  at its time, which sets the variable ``event_NAME`` to ``k`` (its occurrence
  count): a ``StoryboardElementStateCondition`` on the event, or a
  ``VariableCondition`` on the variable, reacts to it.
* The storyboard stops at the run's last recorded time.

Positions, headings and times are written to :data:`DIGITS` decimals (a
micrometre, a microradian, a microsecond) and the headers' dates are fixed, so
one run always exports the same bytes.
"""

from __future__ import annotations

import datetime
import math
import shutil
import xml.etree.ElementTree as ET
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from osc2check.world.limits import mps_to_mmph
from osc2runner.execution.context import EnvironmentChange
from osc2runner.export.recording import ActorTrack, LightTrack, RunRecording
from osc2runner.output.files import write_atomically

__all__ = ["OSC_MINOR_VERSION", "environment_at", "road_file", "scenario_xosc", "write_xosc"]

OSC_MINOR_VERSION = 2
#: the header's date: fixed, so that a run exports the same bytes every time
HEADER_DATE = datetime.datetime(2000, 1, 1)
#: decimals written of positions (m), headings (rad) and times (s)
DIGITS = 6
#: the sun's illuminance (lux) when a scenario places the sun: OSC2 gives no brightness
SUN_ILLUMINANCE = 100_000.0

_VEHICLE_CATEGORIES = {
    "car": "car",
    "bus": "bus",
    "truck": "truck",
    "trailer": "trailer",
    "vru_vehicle": "bicycle",
    "other": "car",
}
_MOTOR_WORDS = ("harley", "kawasaki", "yamaha", "vespa", "motor")
#: okta (0..9) -> OpenSCENARIO's fractional cloud cover
_OKTAS = (
    "zeroOktas",
    "oneOktas",
    "twoOktas",
    "threeOktas",
    "fourOktas",
    "fiveOktas",
    "sixOktas",
    "sevenOktas",
    "eightOktas",
    "nineOktas",
)


def road_file(path: Path) -> Path:
    """The OpenDRIVE file written beside the export ``path``: the same name, ``.xodr``."""
    return path.with_suffix(".xodr")


def write_xosc(recording: RunRecording, path: str | Path) -> list[Path]:
    """Write the run as ``path`` (OpenSCENARIO XML 1.2) and its road network beside it
    (:func:`road_file`), each whole or not at all; returns both paths, the road first."""
    target = Path(path)
    roads = road_file(target)
    if recording.map_file is not None:
        if recording.map_file.resolve() != roads.resolve():
            _copy(recording.map_file, roads)
    else:
        write_atomically(roads, xml_bytes(_builtin_odr(recording)))
    write_atomically(target, xml_bytes(scenario_xosc(recording, roads.name).get_element()))
    return [roads, target]


def xml_bytes(element: ET.Element) -> bytes:
    """An XML document's bytes: UTF-8 with its declaration, indented one space a level
    (a trajectory nests fifteen levels deep: wider indents double the file)."""
    ET.indent(element, space=" ")
    data: bytes = ET.tostring(element, encoding="utf-8", xml_declaration=True)
    return data + b"\n"


def _copy(source: Path, target: Path) -> None:
    temp = target.with_name(f".{target.name}.copy.tmp")
    try:
        shutil.copyfile(source, temp)
        temp.replace(target)
    finally:
        temp.unlink(missing_ok=True)


def _builtin_odr(recording: RunRecording) -> Any:
    from osc2runner.export.xodr import builtin_opendrive

    if recording.builtin is None:
        raise ValueError(f"map {recording.map_name!r} is neither a file nor a built-in road")
    return builtin_opendrive(
        recording.builtin, recording.network, recording.lights, HEADER_DATE.isoformat()
    )


# ---------------------------------------------------------------------- entities


def _entity(xosc: Any, actor: ActorTrack) -> Any:
    centre_z = 0.5 * actor.height
    box = xosc.BoundingBox(actor.width, actor.length, actor.height, -actor.rear_axle, 0.0, centre_z)
    if actor.kind in ("vehicle", "trailer"):
        category = _VEHICLE_CATEGORIES.get(actor.category, "car")
        if category == "bicycle" and any(w in actor.model for w in _MOTOR_WORDS):
            category = "motorbike"
        axles = [
            xosc.Axle(a.max_steer, a.wheel_diameter, a.track_width, a.x, 0.5 * a.wheel_diameter)
            for a in actor.axles
        ]
        front, rear = (axles[0], axles[1]) if len(axles) == 2 else (None, axles[0])
        vehicle = xosc.Vehicle(
            actor.name,
            getattr(xosc.VehicleCategory, category),
            box,
            front,
            rear,
            max(actor.max_speed, 0.0),
            max(actor.max_acceleration, 0.0),
            max(actor.max_deceleration, 0.0),
            mass=actor.mass,
        )
        vehicle.add_property("osc2.model", actor.model)
        return vehicle
    if actor.kind == "pedestrian":
        category = "animal" if actor.category == "animal" else "pedestrian"
        person = xosc.Pedestrian(
            actor.name, actor.mass, getattr(xosc.PedestrianCategory, category), box
        )
        person.add_property("osc2.model", actor.model)
        return person
    thing = xosc.MiscObject(actor.name, actor.mass, xosc.MiscObjectCategory.obstacle, box)
    thing.add_property("osc2.model", actor.model)
    return thing


def _fixed(values: np.ndarray) -> list[float]:
    """Values to :data:`DIGITS` decimals (micrometres, microradians, microseconds)."""
    return [round(float(v), DIGITS) for v in values]


def _headings(yaw: np.ndarray) -> np.ndarray:
    """Headings unwrapped (no jump of 2π between two ticks)."""
    return np.unwrap(yaw) if len(yaw) else yaw


def _trajectory_event(xosc: Any, actor: ActorTrack, times: np.ndarray) -> Any:
    xs, ys = actor.reference_xy()
    hs = _headings(actor.yaw)
    positions = [
        xosc.WorldPosition(x, y, 0.0, h)
        for x, y, h in zip(_fixed(xs), _fixed(ys), _fixed(hs), strict=True)
    ]
    trajectory = xosc.Trajectory(f"{actor.name} as it ran", False)
    trajectory.add_shape(xosc.Polyline(_fixed(times), positions))
    action = xosc.FollowTrajectoryAction(
        trajectory,
        xosc.FollowingMode.position,
        xosc.ReferenceContext.absolute,
        1.0,
        0.0,
    )
    event = xosc.Event(f"{actor.name} follows its trajectory", xosc.Priority.parallel)
    event.add_action(f"{actor.name} trajectory", action)
    event.add_trigger(_at(xosc, 0.0))
    return event


# ---------------------------------------------------------------------- environment


def environment_at(changes: Iterable[EnvironmentChange]) -> dict[str, Any]:
    """The environment after ``changes`` (in order), from the runner's start (dry, calm,
    clear, the ISA atmosphere): ``friction``, ``rain`` and ``snow`` (m/s), ``fog``
    (visual range, m; inf: none), ``wind`` (speed m/s, from-direction rad),
    ``clouds`` (okta), ``temperature`` (K), ``pressure`` (Pa), ``sun`` ((azimuth,
    elevation) rad, or None)."""
    state: dict[str, Any] = {
        "friction": 1.0,
        "rain": 0.0,
        "snow": 0.0,
        "fog": math.inf,
        "wind": (0.0, 0.0),
        "clouds": 0,
        "temperature": 288.15,
        "pressure": 101325.0,
        "sun": None,
    }
    for change in changes:
        v = change.values
        state["friction"] = change.road_friction
        match change.action:
            case "rain" | "snow":
                if "intensity" in v:
                    state[change.action] = float(v["intensity"])
            case "fog":
                if "visual_range" in v:
                    state["fog"] = float(v["visual_range"])
            case "wind":
                speed, direction = state["wind"]
                state["wind"] = (float(v.get("speed", speed)), float(v.get("direction", direction)))
            case "clouds":
                if "cloudiness" in v:
                    state["clouds"] = int(float(v["cloudiness"]))
            case "air":
                state["temperature"] = float(v.get("temperature", state["temperature"]))
                state["pressure"] = float(v.get("pressure", state["pressure"]))
            case "assign_celestial_position":
                if str(v.get("light_source", "sun")) == "sun":
                    azimuth, elevation = state["sun"] or (0.0, 0.0)
                    state["sun"] = (
                        float(v.get("azimuth", azimuth)),
                        float(v.get("elevation", elevation)),
                    )
    return state


def _environment(xosc: Any, state: dict[str, Any], name: str) -> Any:
    if state["rain"] > 0.0:
        precipitation = xosc.Precipitation(xosc.PrecipitationType.rain, mps_to_mmph(state["rain"]))
    elif state["snow"] > 0.0:
        precipitation = xosc.Precipitation(xosc.PrecipitationType.snow, mps_to_mmph(state["snow"]))
    else:
        precipitation = xosc.Precipitation(xosc.PrecipitationType.dry, 0.0)
    speed, source = state["wind"]
    # OSC2: where the wind blows from, clockwise from north; XML: where it blows to, as a yaw
    blows_to = (0.5 * math.pi - (source + math.pi)) % (2.0 * math.pi)
    sun = None
    if state["sun"] is not None:
        azimuth, elevation = state["sun"]
        sun = xosc.Sun(SUN_ILLUMINANCE, azimuth % (2.0 * math.pi), elevation)
    weather = xosc.Weather(
        getattr(xosc.FractionalCloudCover, _OKTAS[min(max(state["clouds"], 0), 9)]),
        atmosphericPressure=min(max(state["pressure"], 80000.0), 120000.0),
        temperature=min(max(state["temperature"], 170.0), 340.0),
        sun=sun,
        fog=xosc.Fog(state["fog"]) if math.isfinite(state["fog"]) else None,
        precipitation=precipitation,
        wind=xosc.Wind(blows_to, speed),
    )
    road = xosc.RoadCondition(state["friction"])
    return xosc.Environment(name, weather=weather, roadcondition=road)


# ---------------------------------------------------------------------- lights and events


def _light_state(bulbs: tuple[tuple[str, str, str], ...]) -> str:
    """A light's bulbs as OpenSCENARIO's state string: ``on``/``off``/``flashing`` per bulb,
    in the light's order, separated by ``;`` (esmini's and OpenDRIVE's convention)."""
    words = {"is_on": "on", "is_flashing": "flashing"}
    return ";".join(words.get(state, "off") for _, _, state in bulbs)


def _signal_id(light: LightTrack) -> str:
    return light.signal or light.name


def _lights(recording: RunRecording) -> list[LightTrack]:
    """The lights a ``TrafficSignalStateAction`` can name: those of the map (their
    ``map_id``) and, on a built-in road, those written into it; a light placed by its
    pose on an OpenDRIVE map (copied as it is) has no signal there."""
    return [light for light in recording.lights if light.signal or recording.map_file is None]


def _at(xosc: Any, time: float) -> Any:
    return xosc.ValueTrigger(
        "at time",
        0.0,
        xosc.ConditionEdge.none,
        xosc.SimulationTimeCondition(time, xosc.Rule.greaterOrEqual),
    )


def _timed_events(xosc: Any, recording: RunRecording) -> list[Any]:
    """The environment changes, light changes and emitted events after tick 0, in time
    order, each an event with its trigger."""
    timed: list[tuple[float, int, Any]] = []
    changes = recording.environment
    for i, change in enumerate(changes):
        if change.tick == 0:
            continue
        event = xosc.Event(f"environment {change.action} #{i + 1}", xosc.Priority.parallel)
        env = _environment(xosc, environment_at(changes[: i + 1]), f"after {change.action}")
        event.add_action(f"set environment #{i + 1}", xosc.EnvironmentAction(env))
        timed.append((change.time, change.tick, event))
    for light in _lights(recording):
        for tick, time, semantic, bulbs in light.changes[1:]:
            label = f"light {light.name} {semantic} at tick {tick}"
            event = xosc.Event(label, xosc.Priority.parallel)
            event.add_action(
                f"light {light.name} {semantic}",
                xosc.TrafficSignalStateAction(_signal_id(light), _light_state(bulbs)),
            )
            timed.append((time, tick, event))
    counts: dict[str, int] = {}
    for emitted in recording.events:
        k = counts[emitted.name] = counts.get(emitted.name, 0) + 1
        event = xosc.Event(f"emit {emitted.name} #{k}", xosc.Priority.parallel)
        event.add_action(
            f"count {emitted.name} #{k}", xosc.VariableSetAction(_variable(emitted.name), k)
        )
        timed.append((emitted.time, emitted.tick, event))
    timed.sort(key=lambda item: item[1])
    for time, _, event in timed:
        event.add_trigger(_at(xosc, time))
    return [event for _, _, event in timed]


def _variable(event: str) -> str:
    return "event_" + "".join(c if c.isalnum() else "_" for c in event)


# ---------------------------------------------------------------------- scenario


def scenario_xosc(recording: RunRecording, road: str) -> Any:
    """The ``scenariogeneration.xosc.Scenario`` of a run whose road network is the file
    ``road`` (relative to the scenario file)."""
    from scenariogeneration import xosc

    times = recording.times
    entities = xosc.Entities()
    init = xosc.Init()
    start_env = [c for c in recording.environment if c.tick == 0]
    init.add_global_action(
        xosc.EnvironmentAction(_environment(xosc, environment_at(start_env), "at the start"))
    )
    for light in _lights(recording):
        _, _, _, bulbs = light.changes[0]
        init.add_global_action(
            xosc.TrafficSignalStateAction(_signal_id(light), _light_state(bulbs))
        )
    act = xosc.Act("replay", _at(xosc, 0.0))
    for actor in recording.actors:
        entities.add_scenario_object(actor.name, _entity(xosc, actor))
        xs, ys = actor.reference_xy()
        if not len(xs):
            continue
        init.add_init_action(
            actor.name,
            xosc.TeleportAction(
                xosc.WorldPosition(*_fixed(np.array([xs[0], ys[0], 0.0, actor.yaw[0]])))
            ),
        )
        if not actor.moves:
            continue
        init.add_init_action(
            actor.name,
            xosc.AbsoluteSpeedAction(
                _fixed(actor.speed[:1])[0],
                xosc.TransitionDynamics(xosc.DynamicsShapes.step, xosc.DynamicsDimension.time, 0),
            ),
        )
        if len(xs) < 2:
            continue
        maneuver = xosc.Maneuver(f"{actor.name} replay")
        maneuver.add_event(_trajectory_event(xosc, actor, times))
        group = xosc.ManeuverGroup(f"{actor.name}")
        group.add_actor(actor.name)
        group.add_maneuver(maneuver)
        act.add_maneuver_group(group)
    timed = _timed_events(xosc, recording)
    if timed:
        maneuver = xosc.Maneuver("world replay")
        for event in timed:
            maneuver.add_event(event)
        group = xosc.ManeuverGroup("world")
        group.add_maneuver(maneuver)
        act.add_maneuver_group(group)
    story = xosc.Story("replay")
    story.add_act(act)
    stop = xosc.ValueTrigger(
        "end of the run",
        0.0,
        xosc.ConditionEdge.rising,
        xosc.SimulationTimeCondition(recording.end_time, xosc.Rule.greaterThan),
        "stop",
    )
    storyboard = xosc.StoryBoard(init, stop)
    storyboard.add_story(story)
    variables = xosc.VariableDeclarations()
    for name in dict.fromkeys(e.name for e in recording.events):
        variables.add_variable(xosc.Variable(_variable(name), xosc.ParameterType.double, 0))
    description = (
        f"replay of scenario {recording.scenario} ({recording.source}, seed {recording.seed}): "
        f"{recording.outcome} at {recording.end_time:g} s; written by osc2run"
    )
    return xosc.Scenario(
        description,
        "osc2run",
        xosc.ParameterDeclarations(),
        entities,
        storyboard,
        xosc.RoadNetwork(road),
        xosc.Catalog(),
        osc_minor_version=OSC_MINOR_VERSION,
        creation_date=HEADER_DATE,
        variable_declaration=variables if recording.events else None,
    )
