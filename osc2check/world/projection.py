"""World coordinates to road coordinates and back, vectorised over many points.

The map between road coordinates ``(road, s, t)`` and the world is the one
:class:`~osc2check.world.network.Road` defines: between two reference-line
samples the reference point moves along the chord and the heading turns
linearly, and a point ``t`` to the left lies along the normal of that heading.
Road → world (:func:`road_to_world`) evaluates it directly. World → road
(:func:`project`) inverts it:

1. **Index** (:mod:`.grid`, built once per network): patches of a few samples,
   widened to the outer lane borders plus a margin, entered in a uniform grid.
2. **Candidates.** A point's cell lists the patches that may contain it; a
   point-in-quadrilateral test keeps those that do (a handful per road nearby,
   a few dozen in a busy junction). Points are processed in chunks, all
   (point, patch) pairs at once in numpy.
3. **Inversion.** On each pair, Newton steps solve ``(Q - P(a)) . T(a) = 0``
   for the fraction ``a`` along a chord (``P`` the chord point, ``T`` the
   interpolated tangent): first on the patch's chord, which names the sample
   segment by its ``s``, then on that segment (stepping to a neighbour when
   the guess missed); then ``t = (Q - P(a)) . N(a)``. A pair counts when
   Newton converged, ``a`` lies in ``[0, 1]`` and ``t`` within the margin.
4. **Lane and choice.** The lane borders interpolated at ``a`` give the lane
   containing ``t``. Where several roads contain a point (junctions, overlapping
   ends) the pair ranks by: inside a drivable lane, inside another lane,
   outside (within the margin); then the difference between the given yaw and
   the lane's direction of travel; then the distance to the lane centre.

Points farther than the margin from every road get road -1. Round trips
world → road → world agree to well under a micrometre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from osc2check.world.arrays import BoolArray, FloatArray, IntArray
from osc2check.world.grid import SpatialIndex
from osc2check.world.network import DRIVING_TYPES, LaneRef, RoadNetwork

__all__ = [
    "Projection",
    "RoadPoint",
    "WorldPose",
    "lane_to_world",
    "network_bounds",
    "on_drivable",
    "past_end",
    "project",
    "road_to_world",
    "to_road",
    "to_world",
]

_CHUNK = 8192  # points per batch
_HEADING_WEIGHT = 10.0  # metres of lateral distance worth one radian of heading difference


@dataclass(frozen=True, slots=True)
class WorldPose:
    """A world position and yaw (rad, counter-clockwise from +x)."""

    x: float
    y: float
    yaw: float


@dataclass(frozen=True, slots=True)
class RoadPoint:
    """A world point in road coordinates.

    Parameters:
        road: road id.
        s, t: road coordinates (``t`` left of the reference line).
        lane: the lane containing the point, or the nearest lane when ``inside`` is False.
        inside: the point lies between the road's outer lane borders.
        drivable: ``inside`` a lane whose type is in ``DRIVING_TYPES``.
        offset: distance left of the lane's centre line, in its direction of travel.
        heading: the reference line's heading at ``s``.
    """

    road: str
    s: float
    t: float
    lane: LaneRef
    inside: bool
    drivable: bool
    offset: float
    heading: float


@dataclass(frozen=True, slots=True)
class Projection:
    """World → road results for N points, one array entry per point.

    ``road`` is the road number (index into ``RoadNetwork.road_ids``, -1 when
    the point is beyond the margin of every road; the other fields are then
    NaN, -1 or 0), ``section`` the lane-section index within the road, ``lane``
    the OpenDRIVE lane id, ``direction`` the lane's direction of travel
    (+1/-1), ``offset`` the distance left of the lane centre in that direction,
    ``heading`` the reference line's heading.
    """

    road: IntArray
    s: FloatArray
    t: FloatArray
    section: IntArray
    lane: IntArray
    direction: IntArray
    inside: BoolArray
    drivable: BoolArray
    offset: FloatArray
    heading: FloatArray

    def point(self, network: RoadNetwork, i: int) -> RoadPoint | None:
        """Entry ``i`` as a :class:`RoadPoint` (None when no road is near)."""
        road = int(self.road[i])
        if road < 0:
            return None
        road_id = network.road_ids[road]
        return RoadPoint(
            road=road_id,
            s=float(self.s[i]),
            t=float(self.t[i]),
            lane=LaneRef(road_id, int(self.section[i]), int(self.lane[i])),
            inside=bool(self.inside[i]),
            drivable=bool(self.drivable[i]),
            offset=float(self.offset[i]),
            heading=float(self.heading[i]),
        )


# ---------------------------------------------------------------- road → world


def road_to_world(
    network: RoadNetwork, road: IntArray, s: FloatArray, t: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """World ``x, y`` and reference heading of road coordinates (road numbers, s, t)."""
    road = np.broadcast_to(np.asarray(road, dtype=np.int64), np.shape(s))
    s = np.asarray(s, dtype=np.float64)
    t = np.broadcast_to(np.asarray(t, dtype=np.float64), s.shape)
    x = np.empty(s.shape)
    y = np.empty(s.shape)
    heading = np.empty(s.shape)
    for number in np.unique(road):
        mask = road == number
        r = network.roads[network.road_ids[int(number)]]
        j, a = _segment(r.s, s[mask])
        h = r.heading[j] + a * (r.heading[j + 1] - r.heading[j])
        px = r.x[j] + a * (r.x[j + 1] - r.x[j])
        py = r.y[j] + a * (r.y[j + 1] - r.y[j])
        x[mask] = px - t[mask] * np.sin(h)
        y[mask] = py + t[mask] * np.cos(h)
        heading[mask] = h
    return x, y, heading


def _segment(samples: FloatArray, s: FloatArray) -> tuple[IntArray, FloatArray]:
    """Segment index and fraction along it for road coordinates ``s`` (clamped to the road)."""
    s = np.clip(s, samples[0], samples[-1])
    j = np.clip(np.searchsorted(samples, s, side="right") - 1, 0, len(samples) - 2)
    span = samples[j + 1] - samples[j]
    a = np.where(span > 0.0, (s - samples[j]) / np.where(span > 0.0, span, 1.0), 0.0)
    return j.astype(np.int64), a


def to_world(network: RoadNetwork, road_id: str, s: float, t: float = 0.0) -> WorldPose:
    """World pose of ``(road_id, s, t)``; yaw is the reference line's heading there."""
    x, y, h = road_to_world(
        network, np.array([network.road_number(road_id)]), np.array([s]), np.array([t])
    )
    return WorldPose(float(x[0]), float(y[0]), _wrap(float(h[0])))


def lane_centre(network: RoadNetwork, ref: LaneRef, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``t`` of lane ``ref``'s centre at ``s`` and its slope ``dt/ds``."""
    road = network.roads[ref.road]
    section = road.sections[ref.section]
    p = section.position(ref.lane)
    samples = road.s[section.start : section.stop]
    centre = 0.5 * (section.borders[p] + section.borders[p + 1])
    j, a = _segment(samples, np.clip(s, section.s0, section.s1))
    t = centre[j] + a * (centre[j + 1] - centre[j])
    span = samples[j + 1] - samples[j]
    slope = np.where(span > 0.0, (centre[j + 1] - centre[j]) / np.where(span > 0, span, 1.0), 0.0)
    return t, slope


def lane_to_world(network: RoadNetwork, ref: LaneRef, s: float, offset: float = 0.0) -> WorldPose:
    """Pose ``offset`` m left of lane ``ref``'s centre at ``s``, yaw along its travel."""
    lane = network.lane(ref)
    road = network.roads[ref.road]
    tc, slope = lane_centre(network, ref, np.array([s]))
    t = float(tc[0]) + offset * lane.direction
    x, y, h = road_to_world(
        network, np.array([network.road_number(ref.road)]), np.array([s]), np.array([t])
    )
    kappa = float(np.interp(s, road.s, road.curvature))
    yaw = float(h[0]) + math.atan2(float(slope[0]), 1.0 - kappa * t)
    if lane.direction < 0:
        yaw += math.pi
    return WorldPose(float(x[0]), float(y[0]), _wrap(yaw))


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def network_bounds(network: RoadNetwork) -> tuple[float, float, float, float]:
    """``(x_min, x_max, y_min, y_max)`` over the outer lane borders of every road."""
    xs: list[FloatArray] = []
    ys: list[FloatArray] = []
    for road in network.roads.values():
        for section in road.sections:
            sl = slice(section.start, section.stop)
            for row in (section.borders[0], section.borders[-1]):
                h = road.heading[sl]
                xs.append(road.x[sl] - row * np.sin(h))
                ys.append(road.y[sl] + row * np.cos(h))
    x = np.concatenate(xs)
    y = np.concatenate(ys)
    return float(np.min(x)), float(np.max(x)), float(np.min(y)), float(np.max(y))


# ---------------------------------------------------------------- world → road


@dataclass(frozen=True, slots=True)
class _Pairs:
    """Every (point, patch) candidate that contains its point, for one chunk."""

    point: IntArray
    sample: IntArray
    s: FloatArray
    t: FloatArray
    heading: FloatArray
    lane_slot: IntArray
    inside: BoolArray
    beyond: FloatArray
    centre: FloatArray


def _in_patch(index: SpatialIndex, patch: IntArray, px: FloatArray, py: FloatArray) -> BoolArray:
    """True where the point lies in its patch's quadrilateral (always for folded patches)."""
    qx, qy = index.quad_x[patch], index.quad_y[patch]
    cross = index.edge_x[patch] * (py[:, None] - qy) - index.edge_y[patch] * (px[:, None] - qx)
    result: BoolArray = np.all(cross >= 0.0, axis=1) | ~index.quad_convex[patch]
    return result


def _pairs(index: SpatialIndex, qx: FloatArray, qy: FloatArray) -> _Pairs:
    ix = np.floor((qx - index.x0) / index.cell).astype(np.int64)
    iy = np.floor((qy - index.y0) / index.cell).astype(np.int64)
    in_grid = (ix >= 0) & (iy >= 0) & (iy < index.ny)
    key = np.where(in_grid, ix * index.ny + iy, -1)
    pos = np.searchsorted(index.keys, key)
    pos_c = np.minimum(pos, len(index.keys) - 1)
    found = in_grid & (index.keys[pos_c] == key)
    start = index.key_start[pos_c]
    counts = np.where(found, index.key_start[pos_c + 1] - start, 0)
    point = np.repeat(np.arange(len(qx)), counts)
    local = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    patch = index.patch[np.repeat(start, counts) + local]
    near = _in_patch(index, patch, qx[point], qy[point])
    point, patch = point[near], patch[near]
    px, py = qx[point], qy[point]
    # Coarse: invert the patch's chord, then pick the fine segment by s.
    lo, hi = index.patch_lo[patch], index.patch_hi[patch]
    a, _, _ = _invert(index, lo, hi, px, py, check=False, steps=2)
    a = np.nan_to_num(a, nan=0.5)
    coarse_s = index.key_s[lo] + np.clip(a, -0.5, 1.5) * (index.key_s[hi] - index.key_s[lo])
    i = np.clip(np.searchsorted(index.key_s, coarse_s, side="right") - 1, lo, hi - 1)
    start_a = (coarse_s - index.key_s[i]) / (index.key_s[i + 1] - index.key_s[i])
    a, t, h = _invert(index, i, i + 1, px, py, a=start_a, steps=2)
    for _ in range(2):  # step to the neighbouring segment when the coarse guess missed it
        step = np.where((a < 0.0) & (i > lo), -1, np.where((a > 1.0) & (i < hi - 1), 1, 0))
        moved = np.flatnonzero(step)
        if len(moved) == 0:
            break
        i[moved] += step[moved]
        a[moved], t[moved], h[moved] = _invert(index, i[moved], i[moved] + 1, px[moved], py[moved])
    on_segment = (a >= -1e-9) & (a <= 1.0 + 1e-9)
    a = np.clip(a, 0.0, 1.0)
    borders = index.borders[i] + a[:, None] * (index.borders[i + 1] - index.borders[i])
    n_rows = index.rows[index.section[i]]
    left = borders[:, 0]
    right = borders[np.arange(len(i)), n_rows - 1]
    count = np.sum(borders > t[:, None], axis=1)
    slot = np.clip(count - 1, 0, n_rows - 2)
    inside = (t <= left) & (t >= right)
    beyond = np.maximum(np.maximum(t - left, right - t), 0.0)
    keep = on_segment & (beyond <= index.margin)
    rows_k = np.arange(len(i))
    centre = 0.5 * (borders[rows_k, slot] + borders[rows_k, slot + 1])
    s = index.s[i] + a * (index.s[i + 1] - index.s[i])
    return _Pairs(
        point=point[keep],
        sample=i[keep],
        s=s[keep],
        t=t[keep],
        heading=h[keep],
        lane_slot=slot[keep].astype(np.int64),
        inside=inside[keep],
        beyond=beyond[keep],
        centre=centre[keep],
    )


def _invert(
    index: SpatialIndex,
    i: IntArray,
    j: IntArray,
    px: FloatArray,
    py: FloatArray,
    check: bool = True,
    a: FloatArray | None = None,
    steps: int = 3,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Fraction ``a`` along the chord from sample ``i`` to ``j`` with the heading turning
    linearly, such that the point lies on the normal there; then its ``t`` and heading.

    With ``check``, ``a`` is NaN where Newton did not converge (a point far outside
    the chord's reach, or near the centre of its curvature).
    """
    x0, y0, h0 = index.x[i], index.y[i], index.heading[i]
    dx, dy, dh = index.x[j] - x0, index.y[j] - y0, index.heading[j] - h0
    rx, ry = px - x0, py - y0
    if a is None:
        a = (rx * dx + ry * dy) / (dx * dx + dy * dy)
    for _ in range(steps):
        h = h0 + a * dh
        c, sn = np.cos(h), np.sin(h)
        ex, ey = rx - a * dx, ry - a * dy
        f = ex * c + ey * sn
        df = -(dx * c + dy * sn) + dh * (-ex * sn + ey * c)
        a = a - f / np.where(np.abs(df) > 1e-12, df, 1e-12)
    h = h0 + a * dh
    c, sn = np.cos(h), np.sin(h)
    ex, ey = rx - a * dx, ry - a * dy
    if check:
        residual = np.abs(ex * c + ey * sn)
        a = np.where(residual <= 1e-7 * (1.0 + np.hypot(dx, dy)), a, np.nan)
    return a, -ex * sn + ey * c, h


def project(
    network: RoadNetwork, x: FloatArray, y: FloatArray, yaw: FloatArray | None = None
) -> Projection:
    """Road coordinates of N world points (see the module docstring for the choice rules)."""
    index = network.spatial_index()
    x = np.atleast_1d(np.asarray(x, dtype=np.float64))
    y = np.atleast_1d(np.asarray(y, dtype=np.float64))
    yaws = None if yaw is None else np.broadcast_to(np.asarray(yaw, dtype=np.float64), x.shape)
    n = len(x)
    out_road = np.full(n, -1, dtype=np.int64)
    out_section = np.full(n, -1, dtype=np.int64)
    out_lane = np.zeros(n, dtype=np.int64)
    out_direction = np.zeros(n, dtype=np.int64)
    out_s = np.full(n, np.nan)
    out_t = np.full(n, np.nan)
    out_offset = np.full(n, np.nan)
    out_heading = np.full(n, np.nan)
    out_inside = np.zeros(n, dtype=bool)
    out_drivable = np.zeros(n, dtype=bool)
    driving = index.type_mask(DRIVING_TYPES)
    for lo in range(0, n, _CHUNK):
        hi = min(n, lo + _CHUNK)
        pairs = _pairs(index, x[lo:hi], y[lo:hi])
        if len(pairs.point) == 0:
            continue
        sec = index.section[pairs.sample]
        drivable = pairs.inside & driving[index.lane_type[sec, pairs.lane_slot]]
        direction = index.lane_direction[sec, pairs.lane_slot]
        score = np.where(pairs.inside, np.where(drivable, 0.0, 1e4), 2e4)
        score = score + np.where(pairs.inside, np.abs(pairs.t - pairs.centre), pairs.beyond)
        if yaws is not None:
            travel = pairs.heading + np.where(direction < 0, math.pi, 0.0)
            diff = np.abs((yaws[lo:hi][pairs.point] - travel + math.pi) % (2 * math.pi) - math.pi)
            score = score + _HEADING_WEIGHT * diff
        best = _argmin_per_group(pairs.point, score)
        p = pairs.point[best] + lo
        b = best
        out_road[p] = index.road[pairs.sample[b]]
        out_section[p] = index.section_index[sec[b]]
        out_lane[p] = index.lane_id[sec[b], pairs.lane_slot[b]]
        out_direction[p] = direction[b]
        out_s[p] = pairs.s[b]
        out_t[p] = pairs.t[b]
        out_offset[p] = (pairs.t[b] - pairs.centre[b]) * direction[b]
        out_heading[p] = pairs.heading[b]
        out_inside[p] = pairs.inside[b]
        out_drivable[p] = drivable[b]
    return Projection(
        road=out_road,
        s=out_s,
        t=out_t,
        section=out_section,
        lane=out_lane,
        direction=out_direction,
        inside=out_inside,
        drivable=out_drivable,
        offset=out_offset,
        heading=out_heading,
    )


def _argmin_per_group(group: IntArray, score: FloatArray) -> IntArray:
    """Index of the lowest score of each run of equal ``group`` values (groups are sorted)."""
    order = np.lexsort((score, group))
    first = np.concatenate(([True], group[order][1:] != group[order][:-1]))
    result: IntArray = order[first]
    return result


def to_road(network: RoadNetwork, x: float, y: float, yaw: float | None = None) -> RoadPoint | None:
    """Road coordinates of one world point (None when no road is within the margin)."""
    result = project(
        network, np.array([x]), np.array([y]), None if yaw is None else np.array([yaw])
    )
    return result.point(network, 0)


def on_drivable(
    network: RoadNetwork, x: FloatArray, y: FloatArray, types: frozenset[str] = DRIVING_TYPES
) -> BoolArray:
    """True for each point inside a lane whose type is in ``types`` on any road."""
    index = network.spatial_index()
    x = np.atleast_1d(np.asarray(x, dtype=np.float64))
    y = np.atleast_1d(np.asarray(y, dtype=np.float64))
    wanted = index.type_mask(types)
    result = np.zeros(len(x), dtype=bool)
    for lo in range(0, len(x), _CHUNK):
        hi = min(len(x), lo + _CHUNK)
        pairs = _pairs(index, x[lo:hi], y[lo:hi])
        sec = index.section[pairs.sample]
        ok = pairs.inside & wanted[index.lane_type[sec, pairs.lane_slot]]
        result[lo + pairs.point[ok]] = True
    return result


def past_end(network: RoadNetwork, x: FloatArray, y: FloatArray, reach: float = 100.0) -> BoolArray:
    """True for points on no road that lie beyond a road end linking to nothing.

    "Beyond" means ahead of the end (within ``reach`` m) and laterally between
    the end's outer lane borders: where a vehicle leaving that end ends up.
    """
    index = network.spatial_index()
    x = np.atleast_1d(np.asarray(x, dtype=np.float64))
    y = np.atleast_1d(np.asarray(y, dtype=np.float64))
    result = np.zeros(len(x), dtype=bool)
    if len(index.ends) == 0:
        return result
    on_road = project(network, x, y).inside
    for ex, ey, h, t_low, t_high in index.ends:
        along = (x - ex) * math.cos(h) + (y - ey) * math.sin(h)
        side = -(x - ex) * math.sin(h) + (y - ey) * math.cos(h)
        result |= (along > 0.0) & (along <= reach) & (side >= t_low) & (side <= t_high)
    result &= ~on_road
    return result
