"""From road records to a :class:`~osc2check.world.network.RoadNetwork`: sampling and linking.

This is where geometry is evaluated, once:

1. **Samples.** Each road's reference line is sampled at a spacing that keeps
   chords within ``tolerance`` (0.1 mm) of the curve and at most ``max_step``
   (1 m) apart, plus every geometry, lane-section, width and lane-offset record
   start, so piecewise profiles are exact at their breaks. Every sample is
   evaluated in closed form or by quadrature (:mod:`.geometry`); headings are
   unwrapped along the road. Lane-section boundaries are sampled twice (the end
   of one section, the start of the next) so lane borders can jump there.
2. **Lane borders.** For each section, the ``t`` of every lane border at every
   sample: the lane offset, plus the widths summed outwards (or the border
   records). Negative widths count as 0.
3. **Directions.** Right-hand traffic drives along ``s`` on the right side,
   left-hand traffic on the left side; a lane's ``direction="reversed"`` flips it.
4. **Lane graph.** Lane *ends* are joined by lane links between sections, by road
   links (with ``contactPoint``) and by junction connections (their lane links;
   which end of the incoming road touches the junction comes from its links, or
   from geometry when they do not say). A lane's successors are the lanes joined
   to the end it drives out of that are entered at their own entry end.

Bad structure (a road without geometry or lane sections, a link to a road or
junction that does not exist, lane ids that are not ``1..n`` outwards) raises
:class:`~osc2check.world.errors.MapError` at the record's line; so does a record
beyond what a road can be, or a map beyond the sample budget (:mod:`.budget`):
both are checked before anything is sampled at their cost. A lane link that
names a lane that does not exist is skipped with a warning: real files have them
(the NCAP crossing links border lane 2 to a lane -2 its connecting road lacks).
"""

from __future__ import annotations

import math
from collections import defaultdict

import numpy as np

from osc2check.world.arrays import FloatArray
from osc2check.world.budget import (
    MAX_COORDINATE,
    MAX_CURVATURE,
    MAX_ELEVATION,
    MAX_LATERAL,
    MAX_ROAD_LENGTH,
    SampleBudget,
    beyond,
    number_text,
)
from osc2check.world.errors import MapError, MapWarning
from osc2check.world.geometry import (
    Geometry,
    cubic_profile,
    evaluate,
    max_curvature,
    sample_spacing,
)
from osc2check.world.grid import MARGIN
from osc2check.world.network import (
    Junction,
    Lane,
    LaneRef,
    LaneSection,
    Road,
    RoadLink,
    RoadNetwork,
)
from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec

__all__ = ["build_network", "lane_width"]

TOLERANCE = 1e-4  # chord-to-curve distance allowed by the sampling (m)
MAX_STEP = 1.0  # longest distance between samples (m)
_SAME_S = 1e-9  # samples closer than this along s are one sample

_End = tuple[LaneRef, int]  # a lane end: 0 at the section start, 1 at its end


def build_network(
    spec: NetworkSpec, tolerance: float = TOLERANCE, max_step: float = MAX_STEP
) -> RoadNetwork:
    """Sample, lay out and link every road of ``spec`` into a :class:`RoadNetwork`."""
    warnings: list[MapWarning] = []
    seen: set[str] = set()
    for road_spec in spec.roads:
        if road_spec.id in seen:
            raise MapError(
                f"road id `{road_spec.id}` is used twice",
                spec.source,
                road_spec.line,
                road_spec.column,
            )
        seen.add(road_spec.id)
    budget = SampleBudget(spec.source)
    roads = {r.id: _build_road(r, spec.source, tolerance, max_step, budget) for r in spec.roads}
    junctions: dict[str, Junction] = {}
    for junction in spec.junctions:
        if junction.id in junctions:
            raise MapError(f"junction id `{junction.id}` is used twice", spec.source, junction.line)
        junctions[junction.id] = junction
    _check_links(spec, roads, junctions)
    successors, predecessors = _lane_graph(spec, roads, warnings)
    signals = tuple(s for r in spec.roads for s in r.signals)
    references = tuple(s for r in spec.roads for s in r.signal_references)
    return RoadNetwork(
        name=spec.name,
        roads=roads,
        junctions=junctions,
        successors=successors,
        predecessors=predecessors,
        signals=signals,
        signal_references=references,
        controllers=spec.controllers,
        crossings=tuple(c for r in spec.roads for c in r.crossings),
        numbering=spec.numbering,
        source=spec.source,
        revision=spec.revision,
        speed_limit=spec.speed_limit,
        description=spec.description,
        warnings=tuple(warnings),
    )


def lane_width(network: RoadNetwork, ref: LaneRef, s: FloatArray) -> FloatArray:
    """Exact width of lane ``ref`` at road coordinates ``s`` (from its records, >= 0)."""
    road = network.roads[ref.road]
    section = road.sections[ref.section]
    lane = network.lane(ref)
    ds = np.asarray(s, dtype=np.float64) - section.s0
    if lane.widths:
        width: FloatArray = np.maximum(cubic_profile(lane.widths, ds), 0.0)
        return width
    # Border records: the width is the distance between the lane's two border rows
    # (row p is the left border of lanes[p], row p + 1 its right border).
    p = section.position(ref.lane)
    s_samples = road.s[section.start : section.stop]
    left = np.interp(s, s_samples, section.borders[p])
    right = np.interp(s, s_samples, section.borders[p + 1])
    result: FloatArray = np.abs(left - right)
    return result


# ---------------------------------------------------------------- roads


def _build_road(
    spec: RoadSpec, source: str | None, tolerance: float, max_step: float, budget: SampleBudget
) -> Road:
    """The road of ``spec``, sampled. Values that overflow (a record beyond what a road
    can be) are found and refused by the checks, not warned about on stderr."""
    with np.errstate(all="ignore"):
        return _sampled_road(spec, source, tolerance, max_step, budget)


def _sampled_road(
    spec: RoadSpec, source: str | None, tolerance: float, max_step: float, budget: SampleBudget
) -> Road:
    def fail(problem: str) -> MapError:
        return MapError(f"road `{spec.id}`: {problem}", source, spec.line, spec.column)

    if spec.length <= 0.0:
        raise fail(f"length must be > 0, got {spec.length:g}")
    if spec.length > MAX_ROAD_LENGTH:
        raise fail(f"length {spec.length:g} m is longer than a road can be ({_LONGEST})")
    if not spec.geometries:
        raise fail("no geometry in <planView>")
    if not spec.sections:
        raise fail("no <laneSection>")
    geometries = tuple(sorted(spec.geometries, key=lambda g: g.s))
    for g in geometries:
        _check_geometry(spec, g, source)
    section_specs = tuple(sorted(spec.sections, key=lambda sec: sec.s))
    for sec in section_specs:
        if not 0.0 <= sec.s < spec.length:
            raise MapError(
                f"road `{spec.id}`: lane section starts at s={sec.s:g}, outside the road "
                f"(0 .. {spec.length:g})",
                source,
                sec.line,
                sec.column,
            )
    starts = [sec.s for sec in section_specs]
    if section_specs[0].s > _SAME_S:
        raise MapError(
            f"road `{spec.id}`: the first lane section starts at s={starts[0]:g}, not 0",
            source,
            section_specs[0].line,
            section_specs[0].column,
        )
    ends = starts[1:] + [spec.length]
    grid = _sample_grid(spec, geometries, section_specs, ends, tolerance, max_step, budget)

    # One sample array per section, each including both of its ends.
    pieces = []
    for s0, s1 in zip(starts, ends, strict=True):
        inner = grid[(grid > s0 + _SAME_S) & (grid < s1 - _SAME_S)]
        pieces.append(np.concatenate(([s0], inner, [s1])))
    s_all = np.concatenate(pieces)
    x, y, heading, curvature = _reference(geometries, s_all)
    _check_reference(spec, geometries, s_all, (x, y, heading, curvature), source)
    offset = cubic_profile(spec.lane_offsets, s_all)
    height = beyond(cubic_profile(spec.elevation, s_all), MAX_ELEVATION)
    if height is not None:
        raise fail(f"its elevation reaches {number_text(height)} m ({_HIGHEST})")

    sections = []
    start = 0
    for index, (sec, s0, s1, piece) in enumerate(
        zip(section_specs, starts, ends, pieces, strict=True)
    ):
        stop = start + len(piece)
        lanes, borders = _section_lanes(spec, sec, index, piece - s0, offset[start:stop], source)
        wide = beyond(borders, MAX_LATERAL)
        if wide is not None:
            raise MapError(
                f"road `{spec.id}`: a lane border of the lane section at s={s0:g} lies "
                f"{number_text(wide)} m beside the reference line ({_WIDEST})",
                source,
                sec.line,
                sec.column,
            )
        spread = float(np.max(borders) - np.min(borders)) + 2 * MARGIN
        budget.take_area((s1 - s0) * spread, f"road `{spec.id}`", sec.line)
        sections.append(
            LaneSection(
                road=spec.id,
                index=index,
                s0=s0,
                s1=s1,
                lanes=lanes,
                start=start,
                stop=stop,
                borders=borders,
                single_side=sec.single_side,
                line=sec.line,
            )
        )
        start = stop
    return Road(
        id=spec.id,
        name=spec.name,
        length=spec.length,
        junction=spec.junction,
        rule=spec.rule,
        predecessor=spec.predecessor,
        successor=spec.successor,
        sections=tuple(sections),
        s=s_all,
        x=x,
        y=y,
        heading=heading,
        curvature=curvature,
        offset=offset,
        geometries=geometries,
        elevation=spec.elevation,
        speed_limit=spec.speed_limit,
        line=spec.line,
    )


_LONGEST = f"the limit is {MAX_ROAD_LENGTH / 1000:g} km"
_FURTHEST = f"the limit is {MAX_COORDINATE:g} m from the origin"
_SHARPEST = f"the limit is {MAX_CURVATURE:g} per metre, a radius of {100 / MAX_CURVATURE:g} cm"
_WIDEST = f"the limit is {MAX_LATERAL:g} m"
_HIGHEST = f"the limit is {MAX_ELEVATION / 1000:g} km up or down"


def _check_geometry(spec: RoadSpec, g: Geometry, source: str | None) -> None:
    """A plan-view record within what a road can be (``budget``): its length, where it
    starts, how sharply it bends."""

    def fail(problem: str) -> MapError:
        return MapError(f"road `{spec.id}`: the {g.kind} at s={g.s:g} {problem}", source, g.line)

    if g.length <= 0.0:
        raise fail(f"has length {g.length:g} (must be > 0)")
    if g.length > MAX_ROAD_LENGTH or abs(g.s) > MAX_ROAD_LENGTH:
        raise fail(f"is longer or further along than a road can be ({_LONGEST})")
    if abs(g.x) > MAX_COORDINATE or abs(g.y) > MAX_COORDINATE:
        raise fail(f"starts at ({g.x:g}, {g.y:g}) ({_FURTHEST})")
    kappa = max_curvature(g)
    if not kappa <= MAX_CURVATURE:  # (NaN too)
        raise fail(
            f"bends more sharply than a road can: curvature {number_text(kappa)} ({_SHARPEST})"
        )


def _check_reference(
    spec: RoadSpec,
    geometries: tuple[Geometry, ...],
    s: FloatArray,
    samples: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
    source: str | None,
) -> None:
    """Every sample of the reference line a number within the limits (a polynomial's
    coefficients may carry it anywhere); the error names the record."""
    x, y, heading, curvature = samples
    for values, limit, what in (
        (x, MAX_COORDINATE, f"reaches x = {{}} m ({_FURTHEST})"),
        (y, MAX_COORDINATE, f"reaches y = {{}} m ({_FURTHEST})"),
        (heading, math.inf, "has a heading of {}"),
        (
            curvature,
            MAX_CURVATURE,
            f"bends more sharply than a road can: curvature {{}} ({_SHARPEST})",
        ),
    ):
        bad = ~np.isfinite(values) | (np.abs(values) > limit)
        if bad.any():
            at = int(np.argmax(bad))
            starts = np.array([g.s for g in geometries])
            g = geometries[max(int(np.searchsorted(starts, s[at], side="right")) - 1, 0)]
            raise MapError(
                f"road `{spec.id}`: the {g.kind} at s={g.s:g} "
                + what.format(number_text(float(values[at]))),
                source,
                g.line,
            )


def _sample_grid(
    spec: RoadSpec,
    geometries: tuple[Geometry, ...],
    sections: tuple[SectionSpec, ...],
    ends: list[float],
    tolerance: float,
    max_step: float,
    budget: SampleBudget,
) -> FloatArray:
    """Sorted, de-duplicated sample positions over ``[0, length]``; their cost is taken
    from ``budget`` before they are made."""
    parts: list[FloatArray] = [np.array([0.0, spec.length])]
    rows = 1 + max(len(sec.lanes) for sec in sections)
    for g in geometries:
        count = max(1, math.ceil(g.length / sample_spacing(g, tolerance, max_step)))
        budget.take(count + 1, rows, f"road `{spec.id}`", g.line)
        parts.append(np.linspace(g.s, g.s + g.length, count + 1))
    parts.append(np.array([r.s for r in spec.lane_offsets]))
    for sec, end in zip(sections, ends, strict=True):
        breaks = [sec.s + w.s for lane in sec.lanes for w in (*lane.widths, *lane.borders)]
        parts.append(np.array([b for b in breaks if b < end]))
    grid = np.unique(np.clip(np.concatenate(parts), 0.0, spec.length))
    keep = np.concatenate(([True], np.diff(grid) > _SAME_S))
    result: FloatArray = grid[keep]
    return result


def _reference(
    geometries: tuple[Geometry, ...], s: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Reference-line pose and curvature at ``s`` (each geometry from its own start)."""
    starts = np.array([g.s for g in geometries])
    which = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(geometries) - 1)
    x = np.empty_like(s)
    y = np.empty_like(s)
    heading = np.empty_like(s)
    curvature = np.empty_like(s)
    for k in np.unique(which):
        mask = which == k
        g = geometries[int(k)]
        samples = evaluate(g, s[mask] - g.s)
        x[mask] = samples.x
        y[mask] = samples.y
        heading[mask] = samples.heading
        curvature[mask] = samples.curvature
    return x, y, np.unwrap(heading), curvature


def _section_lanes(
    road: RoadSpec,
    sec: SectionSpec,
    index: int,
    ds: FloatArray,
    offset: FloatArray,
    source: str | None,
) -> tuple[tuple[Lane, ...], FloatArray]:
    """The section's lanes left to right and the ``t`` of their borders at each sample."""
    by_id: dict[int, LaneSpec] = {}
    for lane in sec.lanes:
        if lane.id in by_id:
            raise MapError(
                f"road `{road.id}`: lane id {lane.id} appears twice in one lane section",
                source,
                lane.line,
                lane.column,
            )
        by_id[lane.id] = lane
    left = sorted((i for i in by_id if i > 0), reverse=True)
    right = sorted((i for i in by_id if i < 0), reverse=True)
    for side, ids in (("left", sorted(left)), ("right", sorted(-i for i in right))):
        if ids != list(range(1, len(ids) + 1)):
            raise MapError(
                f"road `{road.id}`: {side} lane ids must count 1, 2, ... outwards from the "
                f"centre lane, got {', '.join(str(i if side == 'left' else -i) for i in ids)}",
                source,
                sec.line,
                sec.column,
            )
    outer: dict[int, FloatArray] = {}
    for side_ids, sign in ((sorted(left), 1.0), (sorted(right, reverse=True), -1.0)):
        inner = offset
        for lane_id in side_ids:
            lane = by_id[lane_id]
            if lane.widths:
                width = np.maximum(cubic_profile(lane.widths, ds), 0.0)
                inner = inner + sign * width
            elif lane.borders:
                inner = offset + sign * cubic_profile(lane.borders, ds)
            else:
                raise MapError(
                    f"road `{road.id}`: lane {lane_id} has neither <width> nor <border>",
                    source,
                    lane.line,
                    lane.column,
                )
            outer[lane_id] = inner
    rows = [outer[i] for i in left] + [offset] + [outer[i] for i in right]
    lanes = tuple(_lane(road, index, by_id[i], source) for i in (*left, *right))
    return lanes, np.vstack(rows)


def _lane(road: RoadSpec, section: int, spec: LaneSpec, source: str | None) -> Lane:
    along = (spec.id < 0) == (road.rule == "RHT")
    if spec.direction not in (None, "standard", "reversed", "both"):
        raise MapError(
            f"road `{road.id}`: lane {spec.id} has an unknown direction `{spec.direction}` "
            "(expected standard, reversed or both)",
            source,
            spec.line,
            spec.column,
        )
    if spec.direction == "reversed":
        along = not along
    return Lane(
        ref=LaneRef(road.id, section, spec.id),
        type=spec.type,
        direction=1 if along else -1,
        bidirectional=spec.direction == "both",
        widths=spec.widths,
        borders=spec.borders,
        predecessors=spec.predecessors,
        successors=spec.successors,
        speed_limit=spec.speed_limit,
        line=spec.line,
    )


# ---------------------------------------------------------------- links


def _check_links(spec: NetworkSpec, roads: dict[str, Road], junctions: dict[str, Junction]) -> None:
    for road_spec in spec.roads:
        if road_spec.junction is not None and road_spec.junction not in junctions:
            raise MapError(
                f"road `{road_spec.id}` belongs to junction `{road_spec.junction}`, "
                "which does not exist",
                spec.source,
                road_spec.line,
                road_spec.column,
            )
        for link in (road_spec.predecessor, road_spec.successor):
            if link is None:
                continue
            known = roads if link.element_type == "road" else junctions
            if link.element_id not in known:
                raise MapError(
                    f"road `{road_spec.id}` links to {link.element_type} `{link.element_id}`, "
                    "which does not exist",
                    spec.source,
                    link.line,
                )
    for junction in spec.junctions:
        for connection in junction.connections:
            for role, road_id in (
                ("incoming road", connection.incoming_road),
                ("connecting road", connection.connecting_road),
            ):
                if road_id not in roads:
                    raise MapError(
                        f"junction `{junction.id}` connection `{connection.id}`: {role} "
                        f"`{road_id}` does not exist",
                        spec.source,
                        connection.line,
                    )


def _lane_graph(
    spec: NetworkSpec, roads: dict[str, Road], warnings: list[MapWarning]
) -> tuple[dict[LaneRef, tuple[LaneRef, ...]], dict[LaneRef, tuple[LaneRef, ...]]]:
    joins: dict[_End, set[_End]] = defaultdict(set)

    def join(a: _End, b: _End) -> None:
        joins[a].add(b)
        joins[b].add(a)

    def lane_end(road: Road, section: int, lane_id: int, end: int, line: int | None) -> _End | None:
        if road.sections[section].lane(lane_id) is None:
            warnings.append(
                MapWarning(
                    f"link to lane {lane_id} of road `{road.id}` section {section}, "
                    "which does not exist; skipped",
                    spec.source,
                    line,
                )
            )
            return None
        return (LaneRef(road.id, section, lane_id), end)

    def join_ids(
        a: _End, other: Road, section: int, lane_id: int, end: int, line: int | None
    ) -> None:
        b = lane_end(other, section, lane_id, end, line)
        if b is not None:
            join(a, b)

    for road in roads.values():
        last = len(road.sections) - 1
        # Between the road's own lane sections.
        for k in range(last):
            this, after = road.sections[k], road.sections[k + 1]
            for lane in this.lanes:
                for target in lane.successors:
                    join_ids((lane.ref, 1), road, k + 1, target, 0, lane.line)
            for lane in after.lanes:
                for target in lane.predecessors:
                    join_ids((lane.ref, 0), road, k, target, 1, lane.line)
        # Road links to roads (junction links are resolved from the junction below).
        for link, section, end, attr in (
            (road.predecessor, 0, 0, "predecessors"),
            (road.successor, last, 1, "successors"),
        ):
            if link is None or link.element_type != "road":
                continue
            other = roads[link.element_id]
            contact = link.contact_point or _nearest_end(road, end, other)
            other_section = 0 if contact == "start" else len(other.sections) - 1
            other_end = 0 if contact == "start" else 1
            for lane in road.sections[section].lanes:
                for target in getattr(lane, attr):
                    join_ids((lane.ref, end), other, other_section, target, other_end, link.line)
    for junction in spec.junctions:
        for connection in junction.connections:
            incoming = roads[connection.incoming_road]
            connecting = roads[connection.connecting_road]
            c_section = 0 if connection.contact_point == "start" else len(connecting.sections) - 1
            c_end = 0 if connection.contact_point == "start" else 1
            i_end = _incoming_end(incoming, junction.id, connecting, c_end)
            i_section = 0 if i_end == 0 else len(incoming.sections) - 1
            for a, b in connection.lane_links:
                end_a = lane_end(incoming, i_section, a, i_end, connection.line)
                end_b = lane_end(connecting, c_section, b, c_end, connection.line)
                if end_a is not None and end_b is not None:
                    join(end_a, end_b)

    lanes = {lane.ref: lane for road in roads.values() for lane in road.lanes()}
    order = {ref: i for i, ref in enumerate(lanes)}
    successors: dict[LaneRef, tuple[LaneRef, ...]] = {}
    predecessors: dict[LaneRef, tuple[LaneRef, ...]] = {}
    for ref, lane in lanes.items():
        exit_end = 1 if lane.direction > 0 else 0
        after_refs = {
            other
            for other, end in joins.get((ref, exit_end), ())
            if end == (0 if lanes[other].direction > 0 else 1)
        }
        before_refs = {
            other
            for other, end in joins.get((ref, 1 - exit_end), ())
            if end == (1 if lanes[other].direction > 0 else 0)
        }
        successors[ref] = tuple(sorted(after_refs, key=order.__getitem__))
        predecessors[ref] = tuple(sorted(before_refs, key=order.__getitem__))
    return successors, predecessors


def _end_point(road: Road, end: int) -> tuple[float, float]:
    i = 0 if end == 0 else len(road.s) - 1
    return float(road.x[i]), float(road.y[i])


def _nearest_end(road: Road, end: int, other: Road) -> str:
    """``start`` or ``end``: the end of ``other`` nearest to ``road``'s end ``end``."""
    px, py = _end_point(road, end)
    d_start = math.dist((px, py), _end_point(other, 0))
    d_end = math.dist((px, py), _end_point(other, 1))
    return "start" if d_start <= d_end else "end"


def _incoming_end(incoming: Road, junction: str, connecting: Road, c_end: int) -> int:
    """Which end of ``incoming`` (0 start, 1 end) meets ``connecting`` in ``junction``."""
    at_start = _links_to(incoming.predecessor, junction, connecting.id)
    at_end = _links_to(incoming.successor, junction, connecting.id)
    if at_start != at_end:
        return 0 if at_start else 1
    return 0 if _nearest_end(connecting, c_end, incoming) == "start" else 1


def _links_to(link: RoadLink | None, junction: str, road: str) -> bool:
    if link is None:
        return False
    if link.element_type == "junction":
        return link.element_id == junction
    return link.element_id == road
