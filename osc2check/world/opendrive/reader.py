"""OpenDRIVE 1.4-1.8 XML to road records (:mod:`osc2check.world.specs`).

What is read, element by element:

* ``<header>``: ``revMajor``/``revMinor`` (major must be 1), ``name``.
* ``<road>``: ``id``, ``name``, ``length``, ``junction`` (``-1`` for none),
  ``rule`` (``RHT``/``LHT``); ``<link>`` predecessor/successor (``elementType``,
  ``elementId``, ``contactPoint``); the first ``<type><speed max unit>`` as the
  road's speed limit; ``<planView>`` geometries (``line``, ``arc``, ``spiral``,
  ``poly3``, ``paramPoly3`` with ``pRange``); ``<elevationProfile>``;
  ``<lanes>``: ``<laneOffset>`` records and lane sections with their lanes
  (``id``, ``type``, ``direction``, lane links, ``<width>`` or ``<border>``
  records, the first ``<speed>``); ``<signals>``: ``<signal>`` and
  ``<signalReference>`` with their ``<validity>``; ``<objects>``: each ``<object
  type="crosswalk">`` (``id``, ``s``, ``t``, ``hdg``, ``length``, ``width``) as a
  crossing (:class:`~osc2check.world.network.Crossing`).
* ``<junction>``: ``id``, ``name``, ``type``; connections (``incomingRoad``,
  ``connectingRoad`` or, in direct junctions, ``linkedRoad``, ``contactPoint``)
  and their ``<laneLink from to>``.
* ``<controller>``: ``id``, ``name``, ``sequence`` and the ``signalId`` of each
  ``<control>``.

Not read: ``<lateralProfile>`` (superelevation, shape), lane ``<height>``,
``<roadMark>``, ``<material>``, ``<visibility>``, ``<access>``, ``<rule>``,
other ``<objects>``, ``<surface>``, ``<railroad>``, ``<station>``, ``<geoReference>``,
``<offset>``, user data. They change neither where lanes are nor how they link.

Each problem raises :class:`~osc2check.world.errors.MapError` at the element:
a missing required attribute, a value that is not a number or not one of the
allowed words, a geometry of unknown kind or without any, lanes on the wrong
side. Cross-references (links to roads that do not exist) are checked by the
layout step, which knows every road.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from osc2check.world.geometry import Cubic, Geometry
from osc2check.world.network import (
    Connection,
    Controller,
    Crossing,
    Junction,
    RoadLink,
    Signal,
    SignalReference,
)
from osc2check.world.opendrive.xmltree import Element, read_xml
from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec

__all__ = ["read_spec", "spec_from_tree"]

_SPEED_UNITS = {"m/s": 1.0, "km/h": 1.0 / 3.6, "mph": 0.44704}


def read_spec(path: str | Path) -> NetworkSpec:
    """Read the OpenDRIVE file at ``path`` into road records (MapError when it is bad)."""
    file = Path(path)
    return spec_from_tree(read_xml(file), file.stem)


def spec_from_tree(root: Element, name: str) -> NetworkSpec:
    """Road records from an already parsed OpenDRIVE document."""
    if root.tag != "OpenDRIVE":
        raise root.error(f"the root element is <{root.tag}>, not <OpenDRIVE>")
    revision: tuple[int, int] | None = None
    header = root.find("header")
    if header is not None:
        major = header.integer("revMajor", 1)
        minor = header.integer("revMinor", 0)
        if major != 1:
            raise header.error(f"OpenDRIVE {major}.{minor} is not supported (1.x only)")
        revision = (major, minor)
    roads = tuple(_road(e) for e in root.findall("road"))
    if not roads:
        raise root.error("the file has no <road>")
    return NetworkSpec(
        name=name,
        roads=roads,
        junctions=tuple(_junction(e) for e in root.findall("junction")),
        controllers=tuple(_controller(e) for e in root.findall("controller")),
        revision=revision,
        source=root.file,
    )


# ---------------------------------------------------------------- roads


def _road(e: Element) -> RoadSpec:
    road_id = e.text("id")
    junction = e.text("junction", "-1")
    rule = e.text("rule", "RHT")
    if rule not in ("RHT", "LHT"):
        raise e.error(f"<road> attribute `rule` must be RHT or LHT, got {rule!r}")
    predecessor = successor = None
    link = e.find("link")
    if link is not None:
        predecessor = _road_link(link.find("predecessor"))
        successor = _road_link(link.find("successor"))
    plan = e.find("planView")
    if plan is None:
        raise e.error(f"road `{road_id}` has no <planView>")
    lanes = e.find("lanes")
    if lanes is None:
        raise e.error(f"road `{road_id}` has no <lanes>")
    elevation = e.find("elevationProfile")
    signals = e.find("signals")
    objects = e.find("objects")
    return RoadSpec(
        id=road_id,
        name=e.text("name", ""),
        length=e.number("length"),
        junction=None if junction in ("-1", "") else junction,
        geometries=tuple(_geometry(g) for g in plan.findall("geometry")),
        sections=tuple(_section(s) for s in lanes.findall("laneSection")),
        rule="LHT" if rule == "LHT" else "RHT",
        predecessor=predecessor,
        successor=successor,
        lane_offsets=tuple(_cubic(o, "s") for o in lanes.findall("laneOffset")),
        elevation=()
        if elevation is None
        else tuple(_cubic(x, "s") for x in elevation.findall("elevation")),
        speed_limit=_road_speed(e),
        signals=()
        if signals is None
        else tuple(_signal(x, road_id) for x in signals.findall("signal")),
        signal_references=()
        if signals is None
        else tuple(_signal_reference(x, road_id) for x in signals.findall("signalReference")),
        crossings=()
        if objects is None
        else tuple(
            _crossing(x, road_id)
            for x in objects.findall("object")
            if x.text("type", "") == "crosswalk"
        ),
        line=e.line,
        column=e.column,
    )


def _road_link(e: Element | None) -> RoadLink | None:
    if e is None:
        return None
    kind = e.text("elementType")
    if kind not in ("road", "junction"):
        raise e.error(f"<{e.tag}> attribute `elementType` must be road or junction, got {kind!r}")
    contact = e.optional_text("contactPoint")
    if contact not in (None, "start", "end"):
        raise e.error(f"<{e.tag}> attribute `contactPoint` must be start or end, got {contact!r}")
    if kind == "road" and contact is None:
        contact_point: Literal["start", "end"] | None = None
    else:
        contact_point = "start" if contact == "start" else "end" if contact == "end" else None
    return RoadLink(
        element_type="road" if kind == "road" else "junction",
        element_id=e.text("elementId"),
        contact_point=contact_point,
        line=e.line,
    )


def _road_speed(road: Element) -> float | None:
    for road_type in road.findall("type"):
        speed = road_type.find("speed")
        if speed is not None:
            return _speed(speed)
    return None


def _speed(e: Element) -> float | None:
    raw = e.text("max", "")
    if raw in ("", "no limit", "undefined"):
        return None
    unit = e.text("unit", "m/s")
    if unit not in _SPEED_UNITS:
        raise e.error(f"<speed> attribute `unit` must be m/s, km/h or mph, got {unit!r}")
    return e.number("max") * _SPEED_UNITS[unit]


# ---------------------------------------------------------------- geometry


def _geometry(e: Element) -> Geometry:
    s, x, y = e.number("s"), e.number("x"), e.number("y")
    hdg, length = e.number("hdg"), e.number("length")
    if not e.children:
        raise e.error("<geometry> has no line, arc, spiral, poly3 or paramPoly3")
    shape = e.children[0]
    match shape.tag:
        case "line":
            return Geometry("line", s, x, y, hdg, length, line=e.line)
        case "arc":
            return Geometry(
                "arc", s, x, y, hdg, length, curvature=shape.number("curvature"), line=e.line
            )
        case "spiral":
            return Geometry(
                "spiral",
                s,
                x,
                y,
                hdg,
                length,
                curv_start=shape.number("curvStart"),
                curv_end=shape.number("curvEnd"),
                line=e.line,
            )
        case "poly3":
            coefficients = tuple(shape.number(k) for k in ("a", "b", "c", "d"))
            return Geometry("poly3", s, x, y, hdg, length, coefficients=coefficients, line=e.line)
        case "paramPoly3":
            names = ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV")
            p_range = shape.text("pRange", "normalized")
            if p_range not in ("arcLength", "normalized"):
                raise shape.error(
                    f"<paramPoly3> attribute `pRange` must be arcLength or normalized, "
                    f"got {p_range!r}"
                )
            return Geometry(
                "paramPoly3",
                s,
                x,
                y,
                hdg,
                length,
                coefficients=tuple(shape.number(k) for k in names),
                normalized=p_range == "normalized",
                line=e.line,
            )
        case other:
            raise shape.error(
                f"unknown geometry <{other}> (expected line, arc, spiral, poly3 or paramPoly3)"
            )


def _cubic(e: Element, start: str) -> Cubic:
    return Cubic(
        e.number(start), e.number("a"), e.number("b", 0.0), e.number("c", 0.0), e.number("d", 0.0)
    )


# ---------------------------------------------------------------- lanes


def _section(e: Element) -> SectionSpec:
    lanes: list[LaneSpec] = []
    for side, sign in (("left", 1), ("right", -1)):
        group = e.find(side)
        if group is None:
            continue
        for lane in group.findall("lane"):
            spec = _lane(lane)
            if spec.id * sign <= 0:
                raise lane.error(
                    f"lane {spec.id} is in <{side}>, where ids are "
                    f"{'positive' if sign > 0 else 'negative'}"
                )
            lanes.append(spec)
    single = e.text("singleSide", "false")
    return SectionSpec(
        s=e.number("s"),
        lanes=tuple(lanes),
        single_side=single == "true",
        line=e.line,
        column=e.column,
    )


def _lane(e: Element) -> LaneSpec:
    predecessors: list[int] = []
    successors: list[int] = []
    link = e.find("link")
    if link is not None:
        predecessors = [p.integer("id") for p in link.findall("predecessor")]
        successors = [p.integer("id") for p in link.findall("successor")]
    speed = e.find("speed")
    return LaneSpec(
        id=e.integer("id"),
        type=e.text("type", "none"),
        widths=tuple(_cubic(w, "sOffset") for w in e.findall("width")),
        borders=tuple(_cubic(w, "sOffset") for w in e.findall("border")),
        direction=e.optional_text("direction"),
        predecessors=tuple(predecessors),
        successors=tuple(successors),
        speed_limit=None if speed is None else _speed(speed),
        line=e.line,
        column=e.column,
    )


def _crossing(e: Element, road: str) -> Crossing:
    return Crossing(
        id=e.text("id"),
        road=road,
        s=e.number("s"),
        t=e.number("t"),
        hdg=e.number("hdg", 0.0),
        length=e.number("length"),
        width=e.number("width"),
        line=e.line,
    )


# ---------------------------------------------------------------- signals


def _validity(e: Element) -> tuple[tuple[int, int], ...]:
    return tuple((v.integer("fromLane"), v.integer("toLane")) for v in e.findall("validity"))


def _orientation(e: Element) -> str:
    value = e.text("orientation", "none")
    if value not in ("+", "-", "none"):
        raise e.error(f"<{e.tag}> attribute `orientation` must be +, - or none, got {value!r}")
    return value


def _signal(e: Element, road: str) -> Signal:
    dynamic = e.text("dynamic", "no")
    if dynamic not in ("yes", "no"):
        raise e.error(f"<signal> attribute `dynamic` must be yes or no, got {dynamic!r}")
    return Signal(
        id=e.text("id"),
        road=road,
        s=e.number("s"),
        t=e.number("t"),
        orientation=_orientation(e),
        dynamic=dynamic == "yes",
        type=e.text("type", "-1"),
        subtype=e.text("subtype", "-1"),
        country=e.text("country", ""),
        name=e.text("name", ""),
        value=e.optional_number("value"),
        unit=e.text("unit", ""),
        z_offset=e.number("zOffset", 0.0),
        height=e.optional_number("height"),
        h_offset=e.number("hOffset", 0.0),
        validity=_validity(e),
        line=e.line,
    )


def _signal_reference(e: Element, road: str) -> SignalReference:
    return SignalReference(
        id=e.text("id"),
        road=road,
        s=e.number("s"),
        t=e.number("t"),
        orientation=_orientation(e),
        validity=_validity(e),
        line=e.line,
    )


# ---------------------------------------------------------------- junctions


def _junction(e: Element) -> Junction:
    junction_id = e.text("id")
    connections = []
    for c in e.findall("connection"):
        target = c.optional_text("connectingRoad") or c.optional_text("linkedRoad")
        if target is None:
            raise c.error("<connection> has neither `connectingRoad` nor `linkedRoad`")
        contact = c.text("contactPoint", "start")
        if contact not in ("start", "end"):
            raise c.error(
                f"<connection> attribute `contactPoint` must be start or end, got {contact!r}"
            )
        connections.append(
            Connection(
                id=c.text("id"),
                incoming_road=c.text("incomingRoad"),
                connecting_road=target,
                contact_point="start" if contact == "start" else "end",
                lane_links=tuple(
                    (k.integer("from"), k.integer("to")) for k in c.findall("laneLink")
                ),
                line=c.line,
            )
        )
    return Junction(
        id=junction_id,
        name=e.text("name", ""),
        connections=tuple(connections),
        type=e.text("type", "default"),
        line=e.line,
    )


def _controller(e: Element) -> Controller:
    sequence = e.optional_number("sequence")
    return Controller(
        id=e.text("id"),
        name=e.text("name", ""),
        signals=tuple(c.text("signalId") for c in e.findall("control")),
        sequence=None if sequence is None else int(sequence),
        line=e.line,
    )
