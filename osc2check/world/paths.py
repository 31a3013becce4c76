"""Lane centre lines as dense polylines, in the lane's direction of travel.

A :class:`LanePath` is what a vehicle follows: points on the centre line of one
lane (or of a chain of lanes, :func:`join_paths`), ordered the way traffic
drives, with the distance travelled, the heading of travel (continuous, not
wrapped), the signed curvature (positive turning left as driven), the lane
width and the road coordinate ``s`` of each point. Stanley lateral control
reads heading and position, its feed-forward reads curvature, plots read x/y.

The points are the road's reference-line samples moved to the lane centre, so
they are exact at the samples (the OpenDRIVE curve, lane offset and widths
evaluated there). The heading of the centre line is the reference heading plus
``atan2(dt/ds, 1 - k t)``, the curvature its derivative along the centre line's
own arc length: an arc of radius R seen from a lane ``t`` to the left has
curvature ``1 / (R - t)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from osc2check.world.arrays import FloatArray, IntArray
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.projection import WorldPose

__all__ = ["LanePath", "join_paths", "lane_path"]


@dataclass(frozen=True, eq=False)
class LanePath:
    """A centre line in the direction of travel; all arrays share one index.

    Parameters:
        lanes: the lanes the path runs through, in order.
        lane_of: per point, the index in ``lanes`` of the lane it lies on.
        s: road coordinate of each point on its lane's road.
        distance: distance travelled from the first point (m, increasing).
        x, y: world position.
        heading: direction of travel (rad, continuous along the path).
        curvature: signed curvature as driven (1/m, positive turns left).
        width: lane width at the point (m).
        t: road coordinate ``t`` of the centre line at the point (left of the road's
            reference line; a point ``o`` m left of the path, in its direction of travel,
            is at ``t + o`` on a lane driven along ``s`` and ``t - o`` against it).
    """

    lanes: tuple[LaneRef, ...]
    lane_of: IntArray
    s: FloatArray
    distance: FloatArray
    x: FloatArray
    y: FloatArray
    heading: FloatArray
    curvature: FloatArray
    width: FloatArray
    t: FloatArray

    @property
    def length(self) -> float:
        """Length of the path (m)."""
        return float(self.distance[-1])

    def pose_at(self, distance: float) -> WorldPose:
        """Interpolated pose ``distance`` m along the path (clamped to its ends)."""
        d = min(max(distance, 0.0), self.length)
        x = float(np.interp(d, self.distance, self.x))
        y = float(np.interp(d, self.distance, self.y))
        yaw = float(np.interp(d, self.distance, self.heading))
        return WorldPose(x, y, (yaw + math.pi) % (2.0 * math.pi) - math.pi)

    def curvature_at(self, distance: FloatArray | float) -> FloatArray:
        """Curvature interpolated at ``distance`` (arrays welcome)."""
        return np.asarray(np.interp(distance, self.distance, self.curvature), dtype=np.float64)

    def distance_at(self, s: float, lane: int = 0) -> float:
        """Distance along the path of road coordinate ``s`` on ``lanes[lane]``."""
        mask = self.lane_of == lane
        ss, dd = self.s[mask], self.distance[mask]
        if ss[0] > ss[-1]:
            ss, dd = ss[::-1], dd[::-1]
        return float(np.interp(s, ss, dd))


def lane_path(network: RoadNetwork, ref: LaneRef) -> LanePath:
    """The centre line of lane ``ref`` in its direction of travel (cached on the network)."""
    cached = network.path_cache.get(ref)
    if cached is not None:
        return cached
    road = network.roads[ref.road]
    section = road.sections[ref.section]
    lane = network.lane(ref)
    p = section.position(ref.lane)
    sl = slice(section.start, section.stop)
    s = road.s[sl]
    left, right = section.borders[p], section.borders[p + 1]
    t = 0.5 * (left + right)
    width = left - right
    kappa = road.curvature[sl]
    h = road.heading[sl]
    slope = np.gradient(t, s) if len(s) > 2 else np.full_like(s, (t[-1] - t[0]) / (s[-1] - s[0]))
    x = road.x[sl] - t * np.sin(h)
    y = road.y[sl] + t * np.cos(h)
    lean = np.arctan2(slope, 1.0 - kappa * t)
    heading = h + lean
    stretch = np.hypot(1.0 - kappa * t, slope)
    bend = np.gradient(lean, s) if len(s) > 2 else np.zeros_like(s)
    curvature = (kappa + bend) / stretch
    if lane.direction < 0:
        s, x, y, width, t = s[::-1], x[::-1], y[::-1], width[::-1], t[::-1]
        heading = heading[::-1] + math.pi
        curvature = -curvature[::-1]
    distance = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))))
    path = LanePath(
        lanes=(ref,),
        lane_of=np.zeros(len(s), dtype=np.int64),
        s=s.copy(),
        distance=distance,
        x=x,
        y=y,
        heading=np.unwrap(heading),
        curvature=curvature,
        width=width.copy(),
        t=t.copy(),
    )
    network.path_cache[ref] = path
    return path


def join_paths(paths: list[LanePath]) -> LanePath:
    """Paths one after the other as one path; a point repeated at a joint is kept once."""
    if not paths:
        raise ValueError("no path to join")
    lanes: list[LaneRef] = []
    parts: dict[str, list[FloatArray]] = {
        k: [] for k in ("s", "x", "y", "heading", "curvature", "width", "t")
    }
    lane_of: list[IntArray] = []
    last: tuple[float, float, float] | None = None
    for path in paths:
        sl = slice(0, None)
        if last is not None and math.hypot(path.x[0] - last[0], path.y[0] - last[1]) < 1e-6:
            sl = slice(1, None)
        base = len(lanes)
        lanes.extend(path.lanes)
        heading = path.heading[sl]
        if last is not None and len(heading):
            heading = heading + 2.0 * math.pi * round((last[2] - heading[0]) / (2.0 * math.pi))
        for key in ("s", "x", "y", "curvature", "width", "t"):
            parts[key].append(getattr(path, key)[sl])
        parts["heading"].append(heading)
        lane_of.append(path.lane_of[sl] + base)
        last = (float(path.x[-1]), float(path.y[-1]), float(heading[-1]) if len(heading) else 0.0)
    x = np.concatenate(parts["x"])
    y = np.concatenate(parts["y"])
    return LanePath(
        lanes=tuple(lanes),
        lane_of=np.concatenate(lane_of),
        s=np.concatenate(parts["s"]),
        distance=np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y))))),
        x=x,
        y=y,
        heading=np.concatenate(parts["heading"]),
        curvature=np.concatenate(parts["curvature"]),
        width=np.concatenate(parts["width"]),
        t=np.concatenate(parts["t"]),
    )
