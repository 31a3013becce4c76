"""Paths and trajectories in world coordinates, and the controller that tracks them.

A :class:`Polyline` is a path through world points, densely sampled: the
points joined by straight lines (``straight_line``) or by a centripetal
Catmull-Rom spline through every point (``smooth``, the standard's
``path_interpolation``). It answers "where is arc length ``s``" and "where on the
path is this point" (arc length, signed cross-track error, heading).

A trajectory is a polyline with a time for each given point: between two
points the arc length grows linearly in time (constant speed per segment).

:class:`PathTracker` steers a vehicle along a polyline with the Stanley law
on the front axle and a curvature feed-forward (:func:`stanley_steer`, the lane
controller's law too, ``sim/controllers.py``), and :func:`walker_heading` heads
a walker for a point a little ahead on it.

A car cannot turn on the spot: the corner of a ``straight_line`` path is driven
on the arc tangent to both of its lines whose radius is ``v^2 / CORNER_ACCEL``
at the speed the car takes the corner with (:func:`round_corners`; less where
the lines are too short for it). That arc is the least a car at ``v`` can cut
the corner by without more lateral acceleration: ``R (1 - cos(theta / 2))`` for
a corner of angle ``theta``. Smooth paths are followed as given.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from osc2runner.sim.vehicle import VehicleParams

__all__ = [
    "CORNER_ACCEL",
    "PathTracker",
    "Polyline",
    "RoadLine",
    "Trajectory",
    "round_corners",
    "stanley_steer",
    "walker_heading",
]

#: spacing of the samples of a smooth path (m)
SAMPLE_SPACING = 0.25
#: points closer than this are one point (m)
SAME_POINT = 1e-6
#: arc length searched either side of the last projection first (m; see Polyline.project)
_REACH = 10.0
#: lateral acceleration a corner of a ``straight_line`` path is driven with (m/s²): the
#: hardest lane change's peak (``behaviours.driving.LANE_CHANGE_ACCEL["asap"]``)
CORNER_ACCEL = 5.0
#: spacing of the samples of a rounded corner's arc (m)
ARC_SPACING = 0.25
#: spacing of the samples of a path along the road (m)
ROAD_SPACING = 0.5
#: a heading change between two samples above this is a corner, not a curve (rad)
_CORNER = 0.1


class Polyline:
    """A path through world points ``(x, y)``; see the module docstring.

    It remembers where the last point projected (see :meth:`project`): one follower
    per polyline, as the path actions build one per actor.
    """

    _last: tuple[float, float, tuple[float, float, float]] | None

    def __init__(self, points: Sequence[tuple[float, float]], interpolation: str = "straight_line"):
        pts = _distinct(points)
        if len(pts) < 2:
            raise ValueError("a path needs at least two distinct points")
        self.given = pts
        self.interpolation = interpolation
        smooth = interpolation == "smooth" and len(pts) > 2
        self._sample(_catmull_rom(pts) if smooth else pts)
        # the arc length of each given point (the dense samples pass through them)
        self.given_s = np.array([self.project(float(x), float(y))[0] for x, y in pts])
        self._last = None  # the follower starts anywhere

    @classmethod
    def dense(cls, xy: np.ndarray, given: Sequence[int] | None = None) -> Polyline:
        """A polyline through samples ``xy`` as they are: a line already sampled (a path
        with its corners rounded, a path along a road), followed as it is. ``given`` are
        the indices of the points it was made through (all samples by default)."""
        line = cls.__new__(cls)
        line.interpolation = "smooth"  # the samples are the geometry: no corners to round
        line._sample(xy)
        index = np.arange(len(xy)) if given is None else np.asarray(given, dtype=int)
        line.given = xy[index]
        line.given_s = line.s[index]
        return line

    def follower(self) -> Polyline:
        """This line for one more follower: the same samples, its own last projection."""
        line = copy.copy(self)
        line._last = None
        return line

    def driven(self, corner_speeds: Sequence[float], least_radius: float) -> Polyline:
        """The line a car drives for this path: a ``straight_line`` path's corners rounded
        (:func:`round_corners`) for the speed each is taken with (``corner_speeds``, one
        per inner given point), never tighter than ``least_radius``; else the path."""
        if self.interpolation == "smooth" or len(self.given) < 3:
            return self
        radii = [max(v * v / CORNER_ACCEL, least_radius) for v in corner_speeds]
        return Polyline.dense(round_corners(self.given, radii))

    def _sample(self, dense: np.ndarray) -> None:
        self.xy = dense
        seg = np.diff(dense, axis=0)
        self._seg = seg
        self._seg_len = np.hypot(seg[:, 0], seg[:, 1])
        self.s = np.concatenate([[0.0], np.cumsum(self._seg_len)])
        self._heading = np.arctan2(seg[:, 1], seg[:, 0])
        self._curvature: np.ndarray | None = None
        self._last = None
        self._last_segment = 0

    @property
    def curvature(self) -> np.ndarray:
        """The curvature of each segment (1/m, positive to the left): the heading change
        at its two ends over the arc length it spans, averaged; 0 at a sharp corner of a
        ``straight_line`` path (the rounded line a tracker drives has the curvature)."""
        if self._curvature is None:
            turn = np.diff(self._heading)
            turn = (turn + math.pi) % (2.0 * math.pi) - math.pi
            span = 0.5 * (self._seg_len[:-1] + self._seg_len[1:])
            at_vertex = np.where(span > 0.0, turn / np.maximum(span, SAME_POINT), 0.0)
            if self.interpolation != "smooth":
                at_vertex = np.where(np.abs(turn) > _CORNER, 0.0, at_vertex)
            ends = np.concatenate([[0.0], at_vertex, [0.0]])
            if len(ends) > 2:
                ends[0], ends[-1] = ends[1], ends[-2]
            self._curvature = 0.5 * (ends[:-1] + ends[1:])
        return self._curvature

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def at(self, s: float) -> tuple[float, float, float]:
        """``(x, y, heading)`` at arc length ``s`` (clamped to the path)."""
        s = min(max(s, 0.0), self.length)
        i = int(np.searchsorted(self.s, s, side="right")) - 1
        i = min(max(i, 0), len(self._seg_len) - 1)
        u = (s - self.s[i]) / self._seg_len[i]
        x, y = self.xy[i] + u * self._seg[i]
        return float(x), float(y), float(self._heading[i])

    def project(self, x: float, y: float) -> tuple[float, float, float]:
        """``(s, error, heading)`` of the nearest point: arc length, signed distance
        (positive: the point is left of the path) and the path's heading there. Before
        the path's start or past its end, the distance is taken from the line through
        the end segment (a car coming up to the path is steered onto its line).

        The search looks at the segments within ``_REACH`` m of arc length of the last
        projection first (a follower moves a little per tick; on a path that crosses
        itself this keeps to the stretch it is on), and over the whole path on the
        first call, when the nearest point of that window is one of its ends (a nearer
        one may lie beyond) and when it is more than ``_REACH`` m away (a jump). The
        same point asked twice in a row (the tracker's done test and its step, a
        walker's arrival and heading) is answered from the last result.
        """
        last = self._last
        if last is not None and last[0] == x and last[1] == y:
            return last[2]
        p = np.array([x, y])
        n = len(self._seg_len)
        found = None
        if last is not None:
            s_last = last[2][0]
            lo = max(int(np.searchsorted(self.s, s_last - _REACH, side="right")) - 1, 0)
            hi = min(int(np.searchsorted(self.s, s_last + _REACH)), n)
            found = self._nearest(p, lo, hi)
            i, u = found[0], found[1]
            if (
                (i == lo and u <= 0.0 and lo > 0)
                or (i == hi - 1 and u >= 1.0 and hi < n)
                or found[2] > _REACH * _REACH
            ):
                found = None  # a nearer point may lie beyond the window (or it jumped)
        if found is None:
            found = self._nearest(p, 0, n)
        i, u, d2, cross = found
        if (i == 0 and u <= 0.0) or (i == n - 1 and u >= 1.0):
            error = cross / self._seg_len[i]  # before or past an end: off the line through it
        else:
            error = math.copysign(math.sqrt(d2), cross) if cross else 0.0
        result = float(self.s[i] + u * self._seg_len[i]), error, float(self._heading[i])
        self._last = (x, y, result)
        self._last_segment = i
        return result

    def distances(self, x: Sequence[float], y: Sequence[float]) -> np.ndarray:
        """The distance of each point ``(x[k], y[k])`` from the nearest point of the whole
        path (no follower's window: for measuring, not for following)."""
        p = np.column_stack([np.asarray(x, dtype=float), np.asarray(y, dtype=float)])
        rel = p[:, None, :] - self.xy[None, :-1, :]
        u = np.clip((rel * self._seg).sum(axis=2) / self._seg_len**2, 0.0, 1.0)
        gap = rel - u[:, :, None] * self._seg
        distance: np.ndarray = np.sqrt((gap**2).sum(axis=2).min(axis=1))
        return distance

    def _nearest(self, p: np.ndarray, lo: int, hi: int) -> tuple[int, float, float, float]:
        """Segment ``i`` in ``lo .. hi - 1`` nearest ``p``, the fraction along it, the
        squared distance and the cross product that says the side."""
        seg = self._seg[lo:hi]
        rel = p - self.xy[lo:hi]
        u = np.clip((rel * seg).sum(axis=1) / self._seg_len[lo:hi] ** 2, 0.0, 1.0)
        near = self.xy[lo:hi] + u[:, None] * seg
        d2 = ((near - p) ** 2).sum(axis=1)
        k = int(np.argmin(d2))
        cross = seg[k, 0] * rel[k, 1] - seg[k, 1] * rel[k, 0]
        return lo + k, float(u[k]), float(d2[k]), float(cross)


@dataclass(frozen=True)
class Trajectory:
    """A polyline with a time stamp (s, from the phase start) for each given point."""

    path: Polyline
    times: tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.times) != len(self.path.given):
            raise ValueError(
                f"a trajectory needs one time stamp per point: {len(self.path.given)} "
                f"points, {len(self.times)} time stamps"
            )
        if any(b <= a for a, b in zip(self.times, self.times[1:], strict=False)):
            raise ValueError("the time stamps of a trajectory must increase")

    @property
    def duration(self) -> float:
        return self.times[-1] - self.times[0]

    def corner_speeds(self) -> list[float]:
        """The speed at each inner point: the faster of the segments either side of it."""
        speeds = np.diff(self.path.given_s) / np.diff(self.times)
        corners: list[float] = np.maximum(speeds[:-1], speeds[1:]).tolist()
        return corners

    def s_at(self, t: float) -> tuple[float, float]:
        """``(arc length, speed along the path)`` at time ``t`` (clamped to the ends)."""
        times, given = self.times, self.path.given_s
        if t <= times[0]:
            return float(given[0]), 0.0
        if t >= times[-1]:
            return float(given[-1]), 0.0
        i = int(np.searchsorted(times, t, side="right")) - 1
        speed = (given[i + 1] - given[i]) / (times[i + 1] - times[i])
        return float(given[i] + speed * (t - times[i])), float(speed)


class RoadLine(Polyline):
    """A path along a centre line (a lane's, through the lanes it leads into), at an offset
    from it that the given points set: point ``k`` is ``given_o[k]`` m left of the centre
    line where it has run ``given_d[k]`` m. Between two points the offset changes as the
    interpolation says: linearly in the distance along the centre line
    (``straight_line``) or along a cubic through every point's offset (``smooth``, a
    Catmull-Rom spline in the distance). So a path along a curved road through points
    in one lane follows the lane's curve, and one through points in two lanes moves
    across as it goes along.

    ``centre`` is ``(distance, x, y, heading)`` of the centre line's samples (increasing
    distance, continuous heading). When a car drives a ``straight_line`` road path, its
    corners (where the offset's slope changes) are blended over the distance in which a
    car at the corner's speed turns at ``CORNER_ACCEL`` (:meth:`driven`): a parabola in
    the offset, cutting the corner by ``v^2 dm^2 / (8 a)`` for a change of slope ``dm``.
    """

    def __init__(
        self,
        centre: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
        given_d: Sequence[float] | np.ndarray,
        given_o: Sequence[float] | np.ndarray,
        interpolation: str = "straight_line",
    ) -> None:
        d = np.asarray(given_d, dtype=float)
        if len(d) < 2 or np.any(np.diff(d) <= SAME_POINT):
            raise ValueError("the points of a path along the road must follow one another")
        self.centre = centre
        self.given_d = d
        self.given_o = np.asarray(given_o, dtype=float)
        self.interpolation = interpolation
        samples = np.union1d(np.arange(d[0], d[-1], ROAD_SPACING), d)
        self._index = np.searchsorted(samples, d)
        self._d = samples
        self._build(self, self._offsets(samples))

    def _build(self, line: Polyline, offsets: np.ndarray) -> None:
        cd, cx, cy, ch = self.centre
        d = self._d
        heading = np.interp(d, cd, ch)
        x = np.interp(d, cd, cx) - offsets * np.sin(heading)
        y = np.interp(d, cd, cy) + offsets * np.cos(heading)
        line._sample(np.column_stack([x, y]))
        line.given = line.xy[self._index]
        line.given_s = line.s[self._index]

    def _offsets(self, d: np.ndarray, blends: Sequence[float] | None = None) -> np.ndarray:
        """The offset at distances ``d``; ``blends``: the half-length of each inner
        corner's parabola (``straight_line``)."""
        gd, go = self.given_d, self.given_o
        if self.interpolation == "smooth" and len(gd) > 2:
            return _hermite(gd, go, d)
        offsets = np.interp(d, gd, go)
        slopes = np.diff(go) / np.diff(gd)
        for k, half in enumerate(blends or (), start=1):
            change = slopes[k] - slopes[k - 1]
            near = np.abs(d - gd[k]) < half
            u = d[near] - gd[k] + half
            offsets[near] = go[k] + slopes[k - 1] * (d[near] - gd[k]) + change * u * u / (4 * half)
        result: np.ndarray = offsets
        return result

    def driven(self, corner_speeds: Sequence[float], least_radius: float) -> Polyline:
        if self.interpolation == "smooth" or len(self.given_d) < 3:
            return self
        gd, go = self.given_d, self.given_o
        slopes = np.diff(go) / np.diff(gd)
        blends = []
        for k, v in enumerate(corner_speeds, start=1):
            change = abs(float(slopes[k] - slopes[k - 1]))
            half = 0.5 * change * max(v * v / CORNER_ACCEL, least_radius)
            blends.append(min(half, 0.5 * (gd[k] - gd[k - 1]), 0.5 * (gd[k + 1] - gd[k])))
        line = Polyline.__new__(Polyline)
        line.interpolation = "smooth"
        self._build(line, self._offsets(self._d, blends))
        return line


class PathTracker:
    """Stanley steering of a vehicle's front axle along a :class:`Polyline`, with its
    curvature fed forward (:func:`stanley_steer`); ``end`` is the arc length where the
    path is done.

    A ``straight_line`` path's corners are rounded (:func:`round_corners`) when the
    tracker first steps, for the speed the car takes them with: the larger of its
    speed then and the speed it is told to reach (``planned``), or each corner's own
    from ``corner_speeds`` (a trajectory's segment speeds). ``path`` itself, as given,
    measures the progress (``s``, :meth:`done`).
    """

    def __init__(
        self,
        params: VehicleParams,
        path: Polyline,
        *,
        gain: float = 1.5,
        soft_speed: float = 1.0,
        end: float | None = None,
        corner_speeds: Sequence[float] | None = None,
    ) -> None:
        self.params = params
        self.path = path
        self.gain = gain
        self.soft_speed = soft_speed
        self.end = path.length if end is None else end
        self.corner_speeds = corner_speeds
        self.line: Polyline | None = None  # the line steered along (corners rounded)
        self.error = 0.0  # cross-track error of the front axle from ``line``, m (left +)
        self.s = 0.0  # arc length of the front axle's projection on ``path``

    def _driven(self, speed: float, planned: float | None) -> Polyline:
        speeds = self.corner_speeds
        if speeds is None:
            speeds = [max(abs(speed), planned or 0.0)] * max(len(self.path.given) - 2, 0)
        least = self.params.wheelbase / math.tan(self.params.max_steer)
        return self.path.driven(speeds, least)

    def step(
        self, x: float, y: float, yaw: float, speed: float, planned: float | None = None
    ) -> float:
        """The steer input in [-1, 1] for a vehicle at ``(x, y, yaw)`` moving at ``speed``
        and told to reach ``planned`` (m/s)."""
        line = self.line
        if line is None:
            line = self.line = self._driven(speed, planned)
        fx, fy = self.params.front_axle(x, y, yaw)
        self.s = self.path.project(fx, fy)[0]
        _, self.error, heading = line.project(fx, fy)
        kappa = float(line.curvature[line._last_segment])
        delta = stanley_steer(
            self.params.wheelbase,
            kappa,
            heading,
            yaw,
            self.error,
            self.gain,
            self.soft_speed,
            speed,
        )
        return min(max(delta / self.params.max_steer, -1.0), 1.0)

    def done(self, x: float, y: float, yaw: float) -> bool:
        """True once the front axle has reached the end of the path."""
        fx, fy = self.params.front_axle(x, y, yaw)
        return self.path.project(fx, fy)[0] >= self.end - 0.05


def stanley_steer(
    wheelbase: float,
    curvature: float,
    line_heading: float,
    yaw: float,
    error: float,
    gain: float,
    soft_speed: float,
    speed: float,
) -> float:
    """The road-wheel angle (rad) that brings a front axle ``error`` m left of a line back
    onto it: ``atan(L kappa) + (psi_line - asin(L kappa) - psi) - atan(k e / (v_soft + |v|))``.

    The first term feeds the line's curvature forward (the steering of a car on a circle
    of radius ``1 / kappa``); the heading error is taken from the heading such a car has
    when its front axle is on the line (``asin(L kappa)`` less than the line's), so on a
    curve it is zero when the car steers as it should; on a straight line this is the
    classic Stanley law.
    """
    bend = min(max(wheelbase * curvature, -0.99), 0.99)
    line = line_heading - math.asin(bend)
    heading_error = (line - yaw + math.pi) % (2.0 * math.pi) - math.pi
    return math.atan(bend) + heading_error - math.atan2(gain * error, soft_speed + abs(speed))


def round_corners(points: np.ndarray, radii: Sequence[float]) -> np.ndarray:
    """Samples of the polyline through ``points`` with each inner corner ``i`` replaced by
    the arc of radius ``radii[i - 1]`` tangent to its two lines (smaller where the lines
    are too short: each arc takes at most half of a line)."""
    out = [points[0]]
    for i in range(1, len(points) - 1):
        before, after = points[i] - points[i - 1], points[i + 1] - points[i]
        l0, l1 = float(np.hypot(*before)), float(np.hypot(*after))
        u0, u1 = before / l0, after / l1
        turn = math.atan2(u0[0] * u1[1] - u0[1] * u1[0], float(u0 @ u1))
        if abs(turn) < 1e-6:
            continue
        half = math.tan(0.5 * abs(turn))
        tangent = min(radii[i - 1] * half, 0.5 * l0, 0.5 * l1)
        radius = tangent / half
        start = points[i] - tangent * u0
        normal = np.array([-u0[1], u0[0]]) * math.copysign(1.0, turn)  # towards the centre
        centre = start + radius * normal
        n = 2 * max(1, math.ceil(radius * abs(turn) / (2.0 * ARC_SPACING)))  # even: the middle
        for k in range(n + 1):
            a = turn * k / n
            c, s = math.cos(a), math.sin(a)
            r = start - centre
            out.append(centre + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]]))
    out.append(points[-1])
    return _distinct([(float(x), float(y)) for x, y in out])


def walker_heading(path: Polyline, x: float, y: float, lookahead: float = 1.0) -> float:
    """The heading that takes a walker at ``(x, y)`` to the point ``lookahead`` m ahead
    of its projection on ``path``."""
    s, _, heading = path.project(x, y)
    tx, ty, _ = path.at(s + lookahead)
    if math.hypot(tx - x, ty - y) < SAME_POINT:
        return heading
    return math.atan2(ty - y, tx - x)


def _hermite(knots: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """A cubic through ``values`` at increasing ``knots`` (slopes from the neighbours, as
    a Catmull-Rom spline; the end slopes those of the end intervals), at ``at``."""
    slope = np.empty(len(knots))
    slope[1:-1] = (values[2:] - values[:-2]) / (knots[2:] - knots[:-2])
    slope[0] = (values[1] - values[0]) / (knots[1] - knots[0])
    slope[-1] = (values[-1] - values[-2]) / (knots[-1] - knots[-2])
    i = np.clip(np.searchsorted(knots, at, side="right") - 1, 0, len(knots) - 2)
    h = knots[i + 1] - knots[i]
    u = (at - knots[i]) / h
    u2, u3 = u * u, u * u * u
    cubic: np.ndarray = (
        (2 * u3 - 3 * u2 + 1) * values[i]
        + (u3 - 2 * u2 + u) * h * slope[i]
        + (-2 * u3 + 3 * u2) * values[i + 1]
        + (u3 - u2) * h * slope[i + 1]
    )
    return cubic


def _distinct(points: Sequence[tuple[float, float]]) -> np.ndarray:
    out: list[tuple[float, float]] = []
    for x, y in points:
        if not out or math.hypot(x - out[-1][0], y - out[-1][1]) > SAME_POINT:
            out.append((float(x), float(y)))
    return np.array(out, dtype=float).reshape(-1, 2)


def _catmull_rom(points: np.ndarray) -> np.ndarray:
    """Dense samples of the centripetal Catmull-Rom spline through ``points``."""
    ext = np.vstack([2 * points[0] - points[1], points, 2 * points[-1] - points[-2]])
    out = [points[0]]
    for i in range(1, len(ext) - 2):
        p0, p1, p2, p3 = ext[i - 1], ext[i], ext[i + 1], ext[i + 2]
        t0 = 0.0
        t1 = t0 + math.sqrt(max(float(np.hypot(*(p1 - p0))), SAME_POINT))
        t2 = t1 + math.sqrt(max(float(np.hypot(*(p2 - p1))), SAME_POINT))
        t3 = t2 + math.sqrt(max(float(np.hypot(*(p3 - p2))), SAME_POINT))
        n = max(2, int(math.ceil(float(np.hypot(*(p2 - p1))) / SAMPLE_SPACING)))
        for t in np.linspace(t1, t2, n + 1)[1:]:
            a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1
            a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2
            a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3
            b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2
            b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3
            out.append((t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2)
    return np.array(out, dtype=float)
