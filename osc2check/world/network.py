"""The one road-network interface: roads, lanes, junctions, signals, and queries on them.

Every map the toolkit drives on is a :class:`RoadNetwork`: an OpenDRIVE file
(:func:`osc2check.world.opendrive.load_opendrive`) and the built-in straight
maps (:func:`osc2check.world.builtin.builtin_network`) alike, so the checker's
placement, the runner's driving and the editor's hover see one type.

The data is plain: frozen dataclasses and numpy arrays, built once by
:mod:`osc2check.world.layout` and never changed. Queries are functions in
modules of their own (:mod:`.projection`, :mod:`.topology`, :mod:`.numbering`,
:mod:`.paths`, :mod:`.routes`, :mod:`.summary`); the methods of
:class:`RoadNetwork` are one-line doors to them, so code that holds a network
finds everything on it.

Conventions (those of OpenDRIVE):

* **World frame**: x east, y north, z up; yaw counter-clockwise from +x.
* **Road coordinates** ``(s, t)``: ``s`` is the distance along the road's
  reference line from its start (0 .. ``length``), ``t`` the lateral offset to
  the left of the reference line.
* **Lane ids** count outwards from the centre lane 0: positive on the left of
  the reference line, negative on the right. A lane is named across the network
  by :class:`LaneRef` ``(road, section, lane)``: lane ids repeat in every lane
  section.
* **Direction of travel** (``Lane.direction``): +1 along increasing ``s``, -1
  against it. Under right-hand traffic (``rule="RHT"``, the default) the right
  lanes drive along ``s`` and the left lanes against it; ``rule="LHT"`` flips
  both. A lane's ``direction`` attribute (OpenDRIVE 1.7+: ``reversed``, ``both``)
  is honoured.
* **Left and right** of a lane mean left and right *in its direction of travel*.
* **OSC2 lane numbers** (:mod:`.numbering`): among the driving lanes that travel
  the same way in a lane section, 1 is the rightmost (or the leftmost, counting
  from the left); ``numbering`` says how the map's scenarios count.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Literal

from osc2check.world.errors import MapWarning

if TYPE_CHECKING:  # numpy and the geometry are imported where used: the checker's
    # placement on a built-in map reads the start-up cache and needs neither
    from osc2check.world.arrays import BoolArray, FloatArray, IntArray
    from osc2check.world.geometry import Cubic, Geometry
    from osc2check.world.grid import SpatialIndex
    from osc2check.world.paths import LanePath
    from osc2check.world.projection import Projection, RoadPoint, WorldPose
    from osc2check.world.routes import LaneSpan, Route, TurnChoice
    from osc2check.world.summary import NetworkSummary
    from osc2check.world.topology import Neighbours

__all__ = [
    "DRIVING_TYPES",
    "Connection",
    "Controller",
    "Crossing",
    "Junction",
    "Lane",
    "LaneRef",
    "LaneSection",
    "Numbering",
    "Road",
    "RoadLink",
    "RoadNetwork",
    "Signal",
    "SignalReference",
]

Numbering = Literal["from_right", "from_left"]
ContactPoint = Literal["start", "end"]

#: Lane types a vehicle may drive on (OpenDRIVE 1.4-1.8 spellings). Shoulders,
#: borders, hard shoulders (``stop``), parking, sidewalks, biking lanes, medians,
#: curbs and restricted lanes are not: a car on them is off the drivable road.
DRIVING_TYPES: frozenset[str] = frozenset(
    {
        "driving",
        "entry",
        "exit",
        "onRamp",
        "offRamp",
        "connectingRamp",
        "bidirectional",
        "slipLane",
        "mwyEntry",
        "mwyExit",
        "HOV",
        "bus",
        "taxi",
    }
)


@dataclass(frozen=True, slots=True, order=True)
class LaneRef:
    """A lane across the network: road id, lane-section index (0-based), OpenDRIVE lane id."""

    road: str
    section: int
    lane: int

    def __str__(self) -> str:
        return f"road {self.road} section {self.section} lane {self.lane}"


@dataclass(frozen=True, slots=True)
class RoadLink:
    """A road's predecessor or successor: another road (at its start or end) or a junction."""

    element_type: Literal["road", "junction"]
    element_id: str
    contact_point: ContactPoint | None = None
    line: int | None = None


@dataclass(frozen=True, slots=True)
class Lane:
    """One lane of one lane section.

    Parameters:
        ref: where the lane is (road, section, id).
        type: the OpenDRIVE lane type (``driving``, ``shoulder``, ``border``, ...).
        direction: +1 when traffic drives along increasing ``s``, -1 against.
        bidirectional: the file says traffic may use it both ways (``direction="both"``).
        widths: width records (``s`` relative to the section start), or empty when
            the lane's outer border is given by ``borders`` instead.
        borders: outer-border records (``t`` from the centre lane, unsigned), OpenDRIVE's
            alternative to widths.
        predecessors, successors: lane ids the file links this lane to, before and after
            in increasing ``s`` (in the neighbouring section or road).
        speed_limit: the lane's first ``<speed max>`` record in m/s, or None.
        line: source line of the ``<lane>`` element.
    """

    ref: LaneRef
    type: str
    direction: int
    bidirectional: bool = False
    widths: tuple[Cubic, ...] = ()
    borders: tuple[Cubic, ...] = ()
    predecessors: tuple[int, ...] = ()
    successors: tuple[int, ...] = ()
    speed_limit: float | None = None
    line: int | None = None

    @property
    def id(self) -> int:
        """The OpenDRIVE lane id (positive left of the reference line, negative right)."""
        return self.ref.lane

    @property
    def drivable(self) -> bool:
        """True for the lane types in :data:`DRIVING_TYPES`."""
        return self.type in DRIVING_TYPES


@dataclass(frozen=True, eq=False)
class LaneSection:
    """A stretch ``[s0, s1]`` of a road with a fixed set of lanes.

    ``lanes`` runs from the leftmost lane to the rightmost (ids descending, the
    centre lane 0 left out). ``borders`` has one row per lane border, in the same
    order (row ``i`` is the left border of ``lanes[i]``, row ``i + 1`` its right
    border; the centre line, at the lane offset, is among them), and one column
    per reference-line sample ``start .. stop - 1`` of the road.
    """

    road: str
    index: int
    s0: float
    s1: float
    lanes: tuple[Lane, ...]
    start: int
    stop: int
    borders: FloatArray
    single_side: bool = False
    line: int | None = None

    def lane(self, lane_id: int) -> Lane | None:
        """The lane with OpenDRIVE id ``lane_id``, or None."""
        for lane in self.lanes:
            if lane.id == lane_id:
                return lane
        return None

    def position(self, lane_id: int) -> int:
        """Index of ``lane_id`` in ``lanes`` (raises KeyError when absent)."""
        for index, lane in enumerate(self.lanes):
            if lane.id == lane_id:
                return index
        raise KeyError(lane_id)

    @property
    def length(self) -> float:
        """``s1 - s0``."""
        return self.s1 - self.s0


@dataclass(frozen=True, eq=False)
class Road:
    """A road: reference line sampled densely, lane offset, lane sections and links.

    The sample arrays ``s, x, y, heading, curvature, offset`` (``offset`` is the
    lane offset, i.e. the ``t`` of the centre lane) share one index. The section
    boundaries appear twice, once as the last sample of a section and once as the
    first of the next, so each section's samples are a contiguous slice
    ``start:stop`` and lane borders may jump between sections. Between samples the
    road is the chord with the heading interpolated linearly: that map is what
    :mod:`.projection` inverts, and it lies within the sampling tolerance (0.1 mm
    by default) of the OpenDRIVE curve.
    """

    id: str
    name: str
    length: float
    junction: str | None
    rule: Literal["RHT", "LHT"]
    predecessor: RoadLink | None
    successor: RoadLink | None
    sections: tuple[LaneSection, ...]
    s: FloatArray
    x: FloatArray
    y: FloatArray
    heading: FloatArray
    curvature: FloatArray
    offset: FloatArray
    geometries: tuple[Geometry, ...] = ()
    elevation: tuple[Cubic, ...] = ()
    speed_limit: float | None = None
    line: int | None = None

    def section_at(self, s: float) -> LaneSection:
        """The lane section containing ``s`` (the later one at a boundary, the last at the end)."""
        for section in reversed(self.sections):
            if s >= section.s0:
                return section
        return self.sections[0]

    def elevation_at(self, s: FloatArray | float) -> FloatArray:
        """Height of the reference line at ``s`` from the elevation profile (0 without one)."""
        import numpy as np

        from osc2check.world.geometry import cubic_profile

        return cubic_profile(self.elevation, np.asarray(s, dtype=np.float64), before=0.0)

    def lanes(self) -> Iterator[Lane]:
        """Every lane of every section, section by section, left to right."""
        for section in self.sections:
            yield from section.lanes


@dataclass(frozen=True, slots=True)
class Connection:
    """A junction connection: traffic from ``incoming_road`` enters ``connecting_road``.

    ``contact_point`` is the end of the connecting road that touches the incoming
    road; ``lane_links`` pairs incoming lane ids with connecting lane ids. For a
    direct junction (OpenDRIVE 1.7) ``connecting_road`` is the linked road.
    """

    id: str
    incoming_road: str
    connecting_road: str
    contact_point: ContactPoint
    lane_links: tuple[tuple[int, int], ...]
    line: int | None = None


@dataclass(frozen=True, slots=True)
class Junction:
    """A junction: its connections; ``type`` is ``default``, ``virtual`` or ``direct``."""

    id: str
    name: str
    connections: tuple[Connection, ...]
    type: str = "default"
    line: int | None = None

    @property
    def connecting_roads(self) -> tuple[str, ...]:
        """Ids of the roads inside the junction, in order of first mention."""
        return tuple(dict.fromkeys(c.connecting_road for c in self.connections))


@dataclass(frozen=True, slots=True)
class Signal:
    """A ``<signal>`` of a road, kept for traffic lights and signs.

    ``orientation`` is ``+`` (valid for traffic along ``s``), ``-`` (against) or
    ``none`` (both); ``dynamic`` is True for signals that change (traffic lights).
    ``validity`` lists ``(fromLane, toLane)`` ranges; empty means every lane.
    """

    id: str
    road: str
    s: float
    t: float
    orientation: str
    dynamic: bool
    type: str
    subtype: str
    country: str = ""
    name: str = ""
    value: float | None = None
    unit: str = ""
    z_offset: float = 0.0
    height: float | None = None
    h_offset: float = 0.0
    validity: tuple[tuple[int, int], ...] = ()
    line: int | None = None


@dataclass(frozen=True, slots=True)
class SignalReference:
    """A ``<signalReference>``: a signal of another road that also applies at ``(s, t)``."""

    id: str
    road: str
    s: float
    t: float
    orientation: str
    validity: tuple[tuple[int, int], ...] = ()
    line: int | None = None


@dataclass(frozen=True, slots=True)
class Crossing:
    """An ``<object type="crosswalk">`` of a road: a way across it.

    **Choice** (OpenDRIVE gives a crosswalk's box, not its direction): the crossing runs
    along the object's length, the object's ``u`` axis at ``hdg`` from the road's
    direction at ``s`` (a crosswalk across the road has ``hdg`` = ±90°), from
    ``u = -length/2`` (its start) to ``u = +length/2`` (its end) about ``(s, t)``;
    ``width`` is across it.
    """

    id: str
    road: str
    s: float
    t: float
    hdg: float
    length: float
    width: float
    line: int | None = None


@dataclass(frozen=True, slots=True)
class Controller:
    """A ``<controller>``: signals switched together (a traffic-light group)."""

    id: str
    name: str
    signals: tuple[str, ...]
    sequence: int | None = None
    line: int | None = None


@dataclass(eq=False)
class RoadNetwork:
    """A road network: plain data plus the caches the queries build on first use.

    Build one with :func:`osc2check.world.maps.load_map` (a built-in name or an
    ``.xodr`` path), :func:`osc2check.world.opendrive.load_opendrive` or
    :func:`osc2check.world.builtin.builtin_network`.

    Parameters:
        name: the map's name (file stem or built-in name).
        roads: roads by id, in file order.
        junctions: junctions by id.
        successors, predecessors: the lane graph in the direction of travel: the
            lanes a vehicle enters after (before) each lane, across lane sections,
            road links and junctions.
        numbering: how the map's scenarios count lanes (``from_right`` by default;
            the Town06 stand-in counts ``from_left``).
        source: the file the network was read from, or None.
        revision: OpenDRIVE ``(revMajor, revMinor)``, or None.
        speed_limit: the map's speed limit in m/s when it has one for all roads.
        description: one line for humans.
        warnings: problems that were skipped while reading.

    ``path_cache`` holds the lane centre lines :mod:`.paths` has built; ``cache`` what
    other query modules build once per network (carriageways, element tables).
    """

    name: str
    roads: dict[str, Road]
    junctions: dict[str, Junction]
    successors: dict[LaneRef, tuple[LaneRef, ...]]
    predecessors: dict[LaneRef, tuple[LaneRef, ...]]
    signals: tuple[Signal, ...] = ()
    signal_references: tuple[SignalReference, ...] = ()
    controllers: tuple[Controller, ...] = ()
    crossings: tuple[Crossing, ...] = ()
    numbering: Numbering = "from_right"
    source: str | None = None
    revision: tuple[int, int] | None = None
    speed_limit: float | None = None
    description: str = ""
    warnings: tuple[MapWarning, ...] = ()
    road_ids: tuple[str, ...] = field(init=False)
    _index: SpatialIndex | None = field(default=None, init=False, repr=False)
    path_cache: dict[LaneRef, LanePath] = field(default_factory=dict, init=False, repr=False)
    cache: dict[str, object] = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        self.road_ids = tuple(self.roads)

    # ------------------------------------------------------------ structure

    def road(self, road_id: str) -> Road:
        """The road with id ``road_id`` (KeyError when absent)."""
        return self.roads[road_id]

    def road_number(self, road_id: str) -> int:
        """Position of ``road_id`` in ``road_ids``: the road index of vectorised results."""
        return self.road_ids.index(road_id)

    def section(self, ref: LaneRef) -> LaneSection:
        """The lane section ``ref`` lies in."""
        return self.roads[ref.road].sections[ref.section]

    def lane(self, ref: LaneRef) -> Lane:
        """The lane ``ref`` names (KeyError when absent)."""
        lane = self.section(ref).lane(ref.lane)
        if lane is None:
            raise KeyError(ref)
        return lane

    def lane_at(self, road_id: str, s: float, lane_id: int) -> LaneRef:
        """The lane with id ``lane_id`` in the section of ``road_id`` that contains ``s``."""
        section = self.roads[road_id].section_at(s)
        if section.lane(lane_id) is None:
            raise KeyError(LaneRef(road_id, section.index, lane_id))
        return LaneRef(road_id, section.index, lane_id)

    def lanes(self, types: Sequence[str] | frozenset[str] | None = None) -> Iterator[Lane]:
        """Every lane of the network (of the given types only, when given)."""
        for road in self.roads.values():
            for lane in road.lanes():
                if types is None or lane.type in types:
                    yield lane

    def driving_lanes(self) -> Iterator[Lane]:
        """Every lane whose type is in :data:`DRIVING_TYPES`."""
        return self.lanes(DRIVING_TYPES)

    def width(self, ref: LaneRef, s: FloatArray | float) -> FloatArray:
        """Width of lane ``ref`` at road coordinate(s) ``s`` (exact, from its records)."""
        import numpy as np

        from osc2check.world.layout import lane_width

        return lane_width(self, ref, np.asarray(s, dtype=np.float64))

    def bounds(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` of every lane border of every road."""
        from osc2check.world.projection import network_bounds

        return network_bounds(self)

    # ------------------------------------------------------------ coordinates

    def to_world(self, road_id: str, s: float, t: float = 0.0) -> WorldPose:
        """World pose of road coordinates ``(s, t)``; yaw is the reference line's heading."""
        from osc2check.world.projection import to_world

        return to_world(self, road_id, s, t)

    def lane_to_world(self, ref: LaneRef, s: float, offset: float = 0.0) -> WorldPose:
        """World pose ``offset`` m left of lane ``ref``'s centre at ``s``, yaw along its travel."""
        from osc2check.world.projection import lane_to_world

        return lane_to_world(self, ref, s, offset)

    def to_road(self, x: float, y: float, yaw: float | None = None) -> RoadPoint | None:
        """Road coordinates of a world point (None farther than the search margin from roads).

        Where roads overlap (junctions), a point inside a drivable lane wins, then
        the lane whose direction of travel is closest to ``yaw`` (when given), then
        the one whose centre is nearest.
        """
        from osc2check.world.projection import to_road

        return to_road(self, x, y, yaw)

    def project(self, x: FloatArray, y: FloatArray, yaw: FloatArray | None = None) -> Projection:
        """Vectorised :meth:`to_road`: N points in, a :class:`Projection` of arrays out."""
        from osc2check.world.projection import project

        return project(self, x, y, yaw)

    def road_to_world(
        self, road: IntArray | int, s: FloatArray, t: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Vectorised road → world: road numbers (see :meth:`road_number`), s, t → x, y, heading."""
        import numpy as np

        from osc2check.world.projection import road_to_world

        return road_to_world(self, np.asarray(road), s, t)

    def on_drivable(
        self, x: FloatArray, y: FloatArray, types: frozenset[str] = DRIVING_TYPES
    ) -> BoolArray:
        """True for points inside a lane of one of ``types`` (driving lanes by default)."""
        from osc2check.world.projection import on_drivable

        return on_drivable(self, x, y, types)

    def past_end(self, x: FloatArray, y: FloatArray) -> BoolArray:
        """True for points off every road and beyond a road end that links to nothing."""
        from osc2check.world.projection import past_end

        return past_end(self, x, y)

    def signal_pose(self, signal: Signal | SignalReference) -> WorldPose:
        """World position of a signal; yaw faces the traffic it is valid for (``+``: along s)."""
        pose = self.to_world(signal.road, signal.s, signal.t)
        turn = math.pi if signal.orientation == "+" else 0.0
        extra = signal.h_offset if isinstance(signal, Signal) else 0.0
        yaw = (pose.yaw + turn + extra + math.pi) % (2.0 * math.pi) - math.pi
        return replace(pose, yaw=yaw)

    # ------------------------------------------------------------ lanes

    def lane_path(self, ref: LaneRef) -> LanePath:
        """Lane ``ref``'s centre line in its direction of travel (dense, cached)."""
        from osc2check.world.paths import lane_path

        return lane_path(self, ref)

    def neighbours(self, ref: LaneRef) -> Neighbours:
        """The lanes left and right of ``ref`` in its direction of travel."""
        from osc2check.world.topology import neighbours

        return neighbours(self, ref)

    def next_lanes(self, ref: LaneRef) -> tuple[LaneRef, ...]:
        """Lanes a vehicle may enter at the end of ``ref`` (sections, road links, junctions)."""
        return self.successors.get(ref, ())

    def previous_lanes(self, ref: LaneRef) -> tuple[LaneRef, ...]:
        """Lanes a vehicle may come from into the start of ``ref``."""
        return self.predecessors.get(ref, ())

    def osc2_lane_index(self, ref: LaneRef, from_side: Literal["right", "left"] = "right") -> int:
        """OSC2 lane number of ``ref`` among the driving lanes travelling its way (1-based)."""
        from osc2check.world.numbering import osc2_lane_index

        return osc2_lane_index(self, ref, from_side)

    def lane_from_osc2_index(
        self,
        road_id: str,
        s: float,
        index: int,
        direction: int = 1,
        from_side: Literal["right", "left"] = "right",
    ) -> LaneRef:
        """Inverse of :meth:`osc2_lane_index` for the lanes travelling ``direction`` at ``s``."""
        from osc2check.world.numbering import lane_from_osc2_index

        return lane_from_osc2_index(self, road_id, s, index, direction, from_side)

    def scenario_lane(self, ref: LaneRef) -> int:
        """The number the map's scenarios use for ``ref`` (per ``numbering``)."""
        side: Literal["right", "left"] = "left" if self.numbering == "from_left" else "right"
        return self.osc2_lane_index(ref, side)

    def lane_from_scenario(
        self, road_id: str, s: float, number: int, direction: int = 1
    ) -> LaneRef:
        """The lane a scenario's lane ``number`` names (per ``numbering``)."""
        side: Literal["right", "left"] = "left" if self.numbering == "from_left" else "right"
        return self.lane_from_osc2_index(road_id, s, number, direction, side)

    # ------------------------------------------------------------ routes

    def route(
        self,
        start: LaneRef,
        choices: Sequence[TurnChoice] = (),
        seed: int | None = None,
        max_length: float = 2000.0,
        towards: Sequence[str] = (),
    ) -> Route:
        """The chain of lanes from ``start``: at each fork the next of ``choices``, else the
        way to the next road of ``towards``, else seeded."""
        from osc2check.world.routes import plan_route

        return plan_route(self, start, choices, seed, max_length, towards)

    def reachable(self, ref: LaneRef, s: float, distance: float) -> tuple[LaneSpan, ...]:
        """Stretches of lanes reachable ahead of ``s`` on ``ref`` within ``distance`` m."""
        from osc2check.world.routes import reachable_lanes

        return reachable_lanes(self, ref, s, distance)

    # ------------------------------------------------------------ summary

    def summary(self) -> NetworkSummary:
        """Counts and lengths for humans (editor hover, CLI listings)."""
        from osc2check.world.summary import summarize

        return summarize(self)

    def spatial_index(self) -> SpatialIndex:
        """The grid of road patches behind projections (built on first use, then cached)."""
        if self._index is None:
            from osc2check.world.grid import build_index

            self._index = build_index(self)
        return self._index
