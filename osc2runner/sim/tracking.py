"""Paths and trajectories in world coordinates, and the controller that tracks them.

A :class:`Polyline` is a path through world points, densely sampled: the
points joined by straight lines (``straight_line``) or by a centripetal
Catmull-Rom spline through every point (``smooth``, the standard's
``path_interpolation``). It answers "where is arc length ``s``" and "where on the
path is this point" (arc length, signed cross-track error, heading).

A trajectory is a polyline with a time for each given point: between two
points the arc length grows linearly in time (constant speed per segment).

:class:`PathTracker` steers a vehicle along a polyline with the Stanley law
on the front axle (the lane controller's law, ``sim/controllers.py``) and
:func:`walker_heading` heads a walker for a point a little ahead on it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from osc2runner.sim.vehicle import VehicleParams

__all__ = ["PathTracker", "Polyline", "Trajectory", "walker_heading"]

#: spacing of the samples of a smooth path (m)
SAMPLE_SPACING = 0.25
#: points closer than this are one point (m)
SAME_POINT = 1e-6
#: arc length searched either side of the last projection first (m; see Polyline.project)
_REACH = 10.0


class Polyline:
    """A path through world points ``(x, y)``; see the module docstring.

    It remembers where the last point projected (see :meth:`project`): one follower
    per polyline, as the path actions build one per actor.
    """

    def __init__(self, points: Sequence[tuple[float, float]], interpolation: str = "straight_line"):
        pts = _distinct(points)
        if len(pts) < 2:
            raise ValueError("a path needs at least two distinct points")
        self.given = pts
        self.interpolation = interpolation
        dense = _catmull_rom(pts) if interpolation == "smooth" and len(pts) > 2 else pts
        self.xy = dense
        seg = np.diff(dense, axis=0)
        self._seg = seg
        self._seg_len = np.hypot(seg[:, 0], seg[:, 1])
        self.s = np.concatenate([[0.0], np.cumsum(self._seg_len)])
        self._heading = np.arctan2(seg[:, 1], seg[:, 0])
        self._last: tuple[float, float, tuple[float, float, float]] | None = None
        # the arc length of each given point (the dense samples pass through them)
        self.given_s = np.array([self.project(float(x), float(y))[0] for x, y in pts])
        self._last = None  # the follower starts anywhere

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
        (positive: the point is left of the path) and the path's heading there.

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
        error = math.copysign(math.sqrt(d2), cross) if cross else 0.0
        result = float(self.s[i] + u * self._seg_len[i]), error, float(self._heading[i])
        self._last = (x, y, result)
        return result

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


class PathTracker:
    """Stanley steering of a vehicle's front axle along a :class:`Polyline`.

    ``delta = heading error - atan(k e / (v_soft + v))``, as the lane
    controller; ``end`` is the arc length where the path is done.
    """

    def __init__(
        self,
        params: VehicleParams,
        path: Polyline,
        *,
        gain: float = 1.5,
        soft_speed: float = 1.0,
        end: float | None = None,
    ) -> None:
        self.params = params
        self.path = path
        self.gain = gain
        self.soft_speed = soft_speed
        self.end = path.length if end is None else end
        self.error = 0.0  # cross-track error of the front axle, m (left positive)
        self.s = 0.0  # arc length of the front axle's projection

    def step(self, x: float, y: float, yaw: float, speed: float) -> float:
        """The steer input in [-1, 1] for a vehicle at ``(x, y, yaw)``."""
        fx, fy = self.params.front_axle(x, y, yaw)
        self.s, self.error, heading = self.path.project(fx, fy)
        heading_error = (heading - yaw + math.pi) % (2.0 * math.pi) - math.pi
        delta = heading_error - math.atan2(self.gain * self.error, self.soft_speed + abs(speed))
        return min(max(delta / self.params.max_steer, -1.0), 1.0)

    def done(self, x: float, y: float, yaw: float) -> bool:
        """True once the front axle has reached the end of the path."""
        fx, fy = self.params.front_axle(x, y, yaw)
        return self.path.project(fx, fy)[0] >= self.end - 0.05


def walker_heading(path: Polyline, x: float, y: float, lookahead: float = 1.0) -> float:
    """The heading that takes a walker at ``(x, y)`` to the point ``lookahead`` m ahead
    of its projection on ``path``."""
    s, _, heading = path.project(x, y)
    tx, ty, _ = path.at(s + lookahead)
    if math.hypot(tx - x, ty - y) < SAME_POINT:
        return heading
    return math.atan2(ty - y, tx - x)


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
