"""A concrete run as ASAM OSI ground truth: one ``osi3.GroundTruth`` message a control tick.

:func:`write_osi` writes a binary OSI trace (``.osi``: each message its length as
a little-endian uint32, then its bytes; written by asam-osi-utilities'
``SingleTraceWriter``), which OSI tools read (``osi3trace.OSITrace``,
asam-osi-utilities' readers, esmini's and CARLA's OSI consumers). Each message
holds the state of its tick; the map's lanes, which never change, are in the
first message only (as esmini writes its OSI traces: a trace of a run on a
curved map would otherwise repeat 50 kB of lane lines 20 times a second):

* ``timestamp`` the tick's simulated time (tick × control period, to the
  nanosecond); ``version`` the OSI version of the bindings; ``host_vehicle_id``
  the system under test's actor (else ``sut``/``ego``, else the first vehicle);
  ``map_reference`` the OpenDRIVE file the run used or the built-in map's name.
* ``moving_object`` per actor that can move: id (1, 2, ... in the run's actor
  order), bounding-box centre (``z`` half its height), heading, velocity and
  acceleration along the heading, dimensions, type (vehicle, pedestrian, animal),
  vehicle class, ``bbcenter_to_rear``/``bbcenter_to_front`` (axles), the trailer it
  tows, ``model_reference`` (the catalogue's model) and the actor's name in
  ``source_reference``.
* ``stationary_object`` per obstacle.
* ``lane`` and ``lane_boundary`` (first message): every lane of every lane section (driving lanes
  ``TYPE_DRIVING``, lanes of junction roads ``TYPE_INTERSECTION``, others
  ``TYPE_NONDRIVING``), centre lines and borders as polylines within 1 cm of the
  map's geometry, neighbours and boundary ids; boundary types are unknown (road
  marks are not read).
* ``traffic_light``: one per bulb (colour, icon, off / constant / flashing) at the
  light's place.
* ``environmental_conditions``: precipitation and fog as OSI's classes, air
  temperature, pressure and humidity, wind, clouds, the sun when placed.

Road friction has no field in OSI's ground truth (docs/export.md).
"""

from __future__ import annotations

import math
import os
import secrets
from pathlib import Path
from typing import Any

import numpy as np

from osc2check.world.limits import mps_to_mmph
from osc2check.world.network import DRIVING_TYPES
from osc2runner.export.recording import ActorTrack, RunRecording
from osc2runner.export.xosc import environment_at

__all__ = ["BOUNDARY_TOLERANCE", "simplified", "write_osi"]

#: how far a written lane line may leave the map's (m)
BOUNDARY_TOLERANCE = 0.01


def simplified(x: np.ndarray, y: np.ndarray, tolerance: float = BOUNDARY_TOLERANCE) -> np.ndarray:
    """Indices of the points of a polyline to keep so that no point left out lies
    farther than ``tolerance`` from the line through those kept (Ramer-Douglas-Peucker)."""
    n = len(x)
    if n <= 2:
        return np.arange(n)
    keep = np.zeros(n, dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, n - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        dx, dy = x[b] - x[a], y[b] - y[a]
        px, py = x[a + 1 : b] - x[a], y[a + 1 : b] - y[a]
        length = math.hypot(dx, dy)
        if length > 0.0:
            d = np.abs(px * dy - py * dx) / length
        else:
            d = np.hypot(px, py)
        i = int(np.argmax(d))
        if d[i] > tolerance:
            k = a + 1 + i
            keep[k] = True
            stack.extend(((a, k), (k, b)))
    return np.flatnonzero(keep)


# ---------------------------------------------------------------------- static content


def _lanes(recording: RunRecording, gt: Any, first_id: int) -> None:
    """Every lane and lane border of the map into ``gt`` (ids from ``first_id`` on)."""
    from osi3.osi_lane_pb2 import Lane, LaneBoundary

    network = recording.network
    next_id = first_id
    for number, road_id in enumerate(network.road_ids):
        road = network.roads[road_id]
        in_junction = road.junction is not None
        for section in road.sections:
            if not section.lanes:
                continue
            s = road.s[section.start : section.stop]
            road_index = np.full(len(s), number)
            rows = []
            for k in range(section.borders.shape[0]):
                t = section.borders[k]
                x, y, _ = network.road_to_world(road_index, s, t)
                rows.append((x, y, t))
            border_ids = list(range(next_id, next_id + len(rows)))
            next_id += len(rows)
            for k, (x, y, _) in enumerate(rows):
                boundary = gt.lane_boundary.add()
                boundary.id.value = border_ids[k]
                boundary.classification.type = LaneBoundary.Classification.TYPE_UNKNOWN
                for i in simplified(x, y):
                    point = boundary.boundary_line.add()
                    point.position.x, point.position.y = float(x[i]), float(y[i])
            lane_ids = list(range(next_id, next_id + len(section.lanes)))
            next_id += len(section.lanes)
            for i, lane in enumerate(section.lanes):
                entry = gt.lane.add()
                entry.id.value = lane_ids[i]
                c = entry.classification
                if in_junction:
                    c.type = Lane.Classification.TYPE_INTERSECTION
                elif lane.type in DRIVING_TYPES:
                    c.type = Lane.Classification.TYPE_DRIVING
                else:
                    c.type = Lane.Classification.TYPE_NONDRIVING
                t = 0.5 * (section.borders[i] + section.borders[i + 1])
                x, y, _ = network.road_to_world(road_index, s, t)
                for j in simplified(x, y):
                    point = c.centerline.add()
                    point.x, point.y = float(x[j]), float(y[j])
                c.centerline_is_driving_direction = lane.direction > 0
                c.left_lane_boundary_id.add().value = border_ids[i]
                c.right_lane_boundary_id.add().value = border_ids[i + 1]
                if i > 0:
                    c.left_adjacent_lane_id.add().value = lane_ids[i - 1]
                if i + 1 < len(section.lanes):
                    c.right_adjacent_lane_id.add().value = lane_ids[i + 1]
                reference = entry.source_reference.add()
                reference.type = "net.asam.opendrive"
                reference.identifier.extend([road_id, str(lane.id)])


def _vehicle_type(actor: ActorTrack) -> str:
    if actor.kind == "trailer":
        return "TYPE_TRAILER"
    return {
        "car": "TYPE_MEDIUM_CAR",
        "bus": "TYPE_BUS",
        "truck": "TYPE_HEAVY_TRUCK",
        "vru_vehicle": "TYPE_BICYCLE",
    }.get(actor.category, "TYPE_OTHER")


def _static_object(gt: Any, actor: ActorTrack, object_id: int) -> None:
    from osi3.osi_object_pb2 import StationaryObject

    thing = gt.stationary_object.add()
    thing.id.value = object_id
    thing.classification.type = StationaryObject.Classification.TYPE_OTHER
    base = thing.base
    base.dimension.length, base.dimension.width = actor.length, actor.width
    base.dimension.height = actor.height
    base.position.x, base.position.y = float(actor.x[0]), float(actor.y[0])
    base.position.z = 0.5 * actor.height
    base.orientation.yaw = float(actor.yaw[0])
    thing.model_reference = actor.model
    reference = thing.source_reference.add()
    reference.type = "net.asam.openscenario"
    reference.identifier.append(actor.name)


def _template(recording: RunRecording) -> tuple[Any, Any, dict[str, int]]:
    """Two ground-truth messages with what every message has (version, host, map
    reference, obstacles), the second also the lanes (the first message's), and the
    object id of every actor."""
    from osi3 import osi_version_pb2
    from osi3.osi_groundtruth_pb2 import GroundTruth

    gt = GroundTruth()
    version = osi_version_pb2.DESCRIPTOR.GetOptions().Extensions[
        osi_version_pb2.current_interface_version
    ]
    gt.version.CopyFrom(version)
    ids = {actor.name: i + 1 for i, actor in enumerate(recording.actors)}
    if recording.host is not None:
        gt.host_vehicle_id.value = ids[recording.host]
    gt.map_reference = str(recording.map_file) if recording.map_file else recording.map_name
    for actor in recording.actors:
        if not actor.moves:
            _static_object(gt, actor, ids[actor.name])
    first = GroundTruth()
    first.CopyFrom(gt)
    _lanes(recording, first, len(ids) + 1 + 100 * len(recording.lights))
    return gt, first, ids


# ---------------------------------------------------------------------- per tick


def _moving(gt: Any, actor: ActorTrack, object_id: int, k: int, accel: float, trailer: int) -> None:
    from osi3.osi_object_pb2 import MovingObject

    obj = gt.moving_object.add()
    obj.id.value = object_id
    base = obj.base
    base.dimension.length, base.dimension.width = actor.length, actor.width
    base.dimension.height = actor.height
    yaw, speed = float(actor.yaw[k]), float(actor.speed[k])
    c, s = math.cos(yaw), math.sin(yaw)
    base.position.x, base.position.y = float(actor.x[k]), float(actor.y[k])
    base.position.z = 0.5 * actor.height
    base.orientation.yaw = yaw
    base.velocity.x, base.velocity.y = speed * c, speed * s
    base.acceleration.x, base.acceleration.y = accel * c, accel * s
    obj.model_reference = actor.model
    reference = obj.source_reference.add()
    reference.type = "net.asam.openscenario"
    reference.identifier.append(actor.name)
    if actor.kind in ("vehicle", "trailer"):
        obj.type = MovingObject.TYPE_VEHICLE
        obj.vehicle_classification.type = getattr(
            MovingObject.VehicleClassification, _vehicle_type(actor)
        )
        if trailer:
            obj.vehicle_classification.has_trailer = True
            obj.vehicle_classification.trailer_id.value = trailer
        attributes = obj.vehicle_attributes
        attributes.bbcenter_to_rear.x = actor.rear_axle
        if len(actor.axles) == 2:
            attributes.bbcenter_to_front.x = actor.rear_axle + actor.axles[0].x
        if actor.axles:
            attributes.radius_wheel = 0.5 * actor.axles[-1].wheel_diameter
            attributes.number_wheels = 2 * len(actor.axles)
    elif actor.category == "animal":
        obj.type = MovingObject.TYPE_ANIMAL
    else:
        obj.type = MovingObject.TYPE_PEDESTRIAN


def _light_bulbs(gt: Any, recording: RunRecording, tick: int, first_id: int) -> None:
    from osi3.osi_trafficlight_pb2 import TrafficLight

    colours = {"red": "COLOR_RED", "yellow": "COLOR_YELLOW", "green": "COLOR_GREEN"}
    modes = {"is_on": "MODE_CONSTANT", "is_flashing": "MODE_FLASHING"}
    for n, light in enumerate(recording.lights):
        shown = [c for c in light.changes if c[0] <= tick][-1][3]
        for b, (colour, icon, state) in enumerate(shown):
            bulb = gt.traffic_light.add()
            bulb.id.value = first_id + 100 * n + b
            bulb.base.position.x, bulb.base.position.y = light.x, light.y
            bulb.base.position.z = 2.0 + 0.3 * (len(shown) - 1 - b)
            bulb.base.orientation.yaw = light.yaw
            bulb.base.dimension.length, bulb.base.dimension.width = 0.1, 0.3
            bulb.base.dimension.height = 0.3
            cls = bulb.classification
            cls.color = getattr(TrafficLight.Classification, colours.get(colour, "COLOR_OTHER"))
            cls.icon = (
                TrafficLight.Classification.ICON_NONE
                if icon == "circle"
                else TrafficLight.Classification.ICON_OTHER
            )
            cls.mode = getattr(TrafficLight.Classification, modes.get(state, "MODE_OFF"))
            reference = bulb.source_reference.add()
            reference.type = "net.asam.opendrive" if light.signal else "net.asam.openscenario"
            reference.identifier.extend([light.signal or light.name, colour])


_PRECIPITATION = (  # mm/h upper bounds of OSI's classes
    (0.1, "PRECIPITATION_NONE"),
    (0.5, "PRECIPITATION_VERY_LIGHT"),
    (1.9, "PRECIPITATION_LIGHT"),
    (8.1, "PRECIPITATION_MODERATE"),
    (34.0, "PRECIPITATION_HEAVY"),
    (149.0, "PRECIPITATION_VERY_HEAVY"),
    (math.inf, "PRECIPITATION_EXTREME"),
)
_FOG = (  # visual range (m) lower bounds of OSI's classes
    (40000.0, "FOG_EXCELLENT_VISIBILITY"),
    (10000.0, "FOG_GOOD_VISIBILITY"),
    (4000.0, "FOG_MODERATE_VISIBILITY"),
    (2000.0, "FOG_POOR_VISIBILITY"),
    (1000.0, "FOG_MIST"),
    (200.0, "FOG_LIGHT"),
    (50.0, "FOG_THICK"),
    (0.0, "FOG_DENSE"),
)
_CLOUDS = (
    "ZERO",
    "ONE",
    "TWO",
    "THREE",
    "FOUR",
    "FIVE",
    "SIX",
    "SEVEN",
    "EIGHT",
)


def _environment(gt: Any, state: dict[str, Any], humidity: float) -> None:
    from osi3.osi_environment_pb2 import EnvironmentalConditions as E

    env = gt.environmental_conditions
    mmph = mps_to_mmph(max(state["rain"], state["snow"]))
    env.precipitation = getattr(E, next(name for bound, name in _PRECIPITATION if mmph < bound))
    env.fog = getattr(E, next(name for bound, name in _FOG if state["fog"] >= bound))
    env.temperature = state["temperature"]
    env.atmospheric_pressure = state["pressure"]
    env.relative_humidity = 100.0 * humidity
    okta = min(max(state["clouds"], 0), 9)
    cover = "SKY_OBSCURED" if okta == 9 else f"{_CLOUDS[okta]}_OKTAS"
    env.clouds.fractional_cloud_cover = getattr(E.CloudLayer, f"FRACTIONAL_CLOUD_COVER_{cover}")
    speed, source = state["wind"]
    env.wind.speed = speed
    env.wind.origin_direction = (0.5 * math.pi - source) % (2.0 * math.pi)
    if state["sun"] is not None:
        env.sun.azimuth, env.sun.elevation = state["sun"]


def ground_truths(recording: RunRecording) -> Any:
    """The run's ground-truth messages, one a recorded tick, in order (a generator)."""
    template, first, ids = _template(recording)
    light_id = len(ids) + 1
    trailers = {a.towed_by: ids[a.name] for a in recording.actors if a.towed_by}
    accel = {a.name: _acceleration(a.speed, recording.dt) for a in recording.actors}
    changes = recording.environment
    for k, tick in enumerate(recording.ticks):
        gt = type(template)()
        gt.CopyFrom(first if k == 0 else template)
        ns = round(int(tick) * recording.dt * 1e9)
        gt.timestamp.seconds, gt.timestamp.nanos = divmod(ns, 1_000_000_000)
        for actor in recording.actors:
            if actor.moves:
                tows = trailers.get(actor.name, 0)
                _moving(gt, actor, ids[actor.name], k, accel[actor.name][k], tows)
        _light_bulbs(gt, recording, int(tick), light_id)
        so_far = [c for c in changes if c.tick <= tick]
        humidity = next(
            (float(c.values["relative_humidity"]) for c in reversed(so_far)
             if c.action == "air" and "relative_humidity" in c.values),
            0.5,
        )  # fmt: skip
        _environment(gt, environment_at(so_far), humidity)
        yield gt


def _acceleration(speed: np.ndarray, dt: float) -> np.ndarray:
    """The change of speed over the last tick (what telemetry's ``accel`` is)."""
    if len(speed) < 2:
        return np.zeros(len(speed))
    return np.concatenate(([0.0], np.diff(speed) / dt))


def write_osi(recording: RunRecording, path: str | Path) -> Path:
    """Write the run's ground truth as the binary OSI trace ``path`` (``.osi``), whole or
    not at all (written beside it, then renamed); returns the path."""
    from osi_utilities import SingleTraceWriter

    target = Path(path)
    staging = target.with_name(f".{target.stem}.{secrets.token_hex(4)}.osi")
    writer = SingleTraceWriter()
    try:
        if not writer.open(staging):
            raise OSError(f"{target}: cannot be written")
        for message in ground_truths(recording):
            if not writer.write_message(message):
                raise OSError(f"{target}: a ground-truth message cannot be written")
        writer.close()
        os.replace(staging, target)
    finally:
        writer.close()
        staging.unlink(missing_ok=True)
    return target
