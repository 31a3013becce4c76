"""Following moving actors on a map, tick after tick, without searching the map each time.

A vehicle moves a few metres per control tick at most, so where it was at the last
tick is a good guess of where it is now. :class:`PathCursor` keeps the segment of a
lane path (:class:`~osc2check.world.paths.LanePath`) the last point projected onto
and steps from there; :class:`RoadLocator` gives an actor's road coordinates from
the path it follows while it is inside that path's lane, else from the road it
was last on (a local inversion of that road's samples, as :mod:`.projection`
does for many points), and falls back to the network's full projection only
when the actor has left both. Everything here is plain Python on floats: for
one or two actors per call that is several times faster than the vectorised
projection, whose fixed cost is numpy's.

Following the path also settles which road an actor is on where roads overlap:
at a junction entry the connecting roads of every turn start together, and the
path the actor drives says which of them it takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from osc2check.world.arrays import IntArray
from osc2check.world.grid import SpatialIndex
from osc2check.world.network import DRIVING_TYPES, Lane, LaneRef, RoadNetwork
from osc2check.world.paths import LanePath

__all__ = ["PathCursor", "PathPoint", "RoadLocator", "RoadPosition"]


@dataclass(slots=True)  # not frozen: made several times per tick, and never changed
class PathPoint:
    """A point projected onto a path: segment ``index`` (``index .. index + 1``) and the
    ``fraction`` along it, the distance along the path (below 0 or beyond its length
    before its start or after its end), the offset left of it, and the path's heading
    and curvature there."""

    index: int
    fraction: float
    distance: float
    offset: float
    heading: float
    curvature: float


class PathCursor:
    """Projects points onto one path, starting from the segment of the last projection."""

    __slots__ = (
        "path",
        "index",
        "length",
        "_x",
        "_y",
        "_d",
        "_h",
        "_k",
        "_last",
        "width",
        "s",
        "t",
        "lane_of",
        "lane_table",
    )

    def __init__(self, path: LanePath) -> None:
        self.path = path
        self._x = path.x.tolist()
        self._y = path.y.tolist()
        self._d = path.distance.tolist()
        self._h = path.heading.tolist()
        self._k = path.curvature.tolist()
        self.width: list[float] = path.width.tolist()
        self.s: list[float] = path.s.tolist()
        self.t: list[float] = path.t.tolist()
        self.lane_of: list[int] = path.lane_of.tolist()
        # per lane of the path: (ref, lane, OSC2 number), filled by the first RoadLocator
        self.lane_table: list[tuple[LaneRef, Lane, int | None]] | None = None
        self.length = path.length
        self._last = len(self._x) - 2  # the last segment
        self.index = -1  # no projection yet

    def seek(self, x: float, y: float) -> None:
        """Start from the path point nearest ``(x, y)`` (after a jump)."""
        d2 = (self.path.x - x) ** 2 + (self.path.y - y) ** 2
        self.index = min(int(np.argmin(d2)), max(self._last, 0))

    def locate(self, x: float, y: float) -> PathPoint:
        """Where ``(x, y)`` projects onto the path."""
        if self.index < 0:
            self.seek(x, y)
        xs, ys = self._x, self._y
        i = self.index
        last = self._last
        if last < 0:  # a single point
            return PathPoint(0, 0.0, 0.0, 0.0, self._h[0], self._k[0])
        for _ in range(200):
            x0, y0 = xs[i], ys[i]
            dx, dy = xs[i + 1] - x0, ys[i + 1] - y0
            length2 = dx * dx + dy * dy
            a = ((x - x0) * dx + (y - y0) * dy) / length2 if length2 > 0.0 else 0.0
            if a < 0.0 and i > 0:  # jump by the segments a suggests (they are about even)
                i = max(i - max(int(-a), 1), 0)
            elif a > 1.0 and i < last:
                i = min(i + max(int(a), 1), last)
            else:
                break
        self.index = i
        length = math.sqrt(length2) if length2 > 0.0 else 1.0
        offset = (dx * (y - y0) - dy * (x - x0)) / length
        d0, h0, k0 = self._d[i], self._h[i], self._k[i]
        distance = d0 + a * (self._d[i + 1] - d0)
        return PathPoint(
            i,
            a,
            distance,
            offset,
            h0 + a * (self._h[i + 1] - h0),
            k0 + a * (self._k[i + 1] - k0),
        )


@dataclass(slots=True)  # not frozen: made per actor per tick, and never changed
class RoadPosition:
    """Road coordinates of an actor (``road`` None when it is near no road).

    ``lane`` is the OpenDRIVE id of the lane it is in (or nearest to, when not
    ``inside`` the road), ``offset`` its distance left of that lane's centre in the
    lane's direction of travel, ``drivable`` whether it stands in a driving lane (of
    this road or another: roads overlap in junctions), ``number`` the OSC2 number of a
    driving lane counted from the right in its direction of travel.
    """

    road: str | None
    section: int
    lane: int
    s: float
    t: float
    offset: float
    direction: int
    inside: bool
    drivable: bool
    number: int | None

    @property
    def ref(self) -> LaneRef | None:
        return LaneRef(self.road, self.section, self.lane) if self.road is not None else None


OFF_MAP = RoadPosition(None, -1, 0, math.nan, math.nan, math.nan, 0, False, False, None)


class _RoadSamples:
    """One road's samples as Python floats, which section each segment is in, and the
    number of its first section among all the network's (the spatial index's order)."""

    __slots__ = ("x", "y", "h", "s", "section", "columns", "count", "first_section")

    def __init__(self, network: RoadNetwork, road_id: str) -> None:
        road = network.roads[road_id]
        self.first_section = 0
        for other_id, other in network.roads.items():
            if other_id == road_id:
                break
            self.first_section += len(other.sections)
        self.x = road.x.tolist()
        self.y = road.y.tolist()
        self.h = road.heading.tolist()
        self.s = road.s.tolist()
        self.count = len(self.s)
        self.section = [0] * max(self.count - 1, 1)
        self.columns: list[list[list[float]]] = []
        for section in road.sections:
            for j in range(section.start, max(section.stop - 1, section.start)):
                self.section[j] = section.index
            self.columns.append(section.borders.T.tolist())


def _cell_key(index: SpatialIndex, x: float, y: float) -> int:
    """The grid cell of ``(x, y)`` as :mod:`.projection` finds it (-1 outside the grid)."""
    ix = math.floor((x - index.x0) / index.cell)
    iy = math.floor((y - index.y0) / index.cell)
    return ix * index.ny + iy if ix >= 0 and 0 <= iy < index.ny else -1


def _cell_patches(index: SpatialIndex, key: int) -> IntArray | None:
    """The patches entered in cell ``key`` (None when there are none)."""
    if key < 0:
        return None
    pos = int(np.searchsorted(index.keys, key))
    if pos >= len(index.keys) or int(index.keys[pos]) != key:
        return None
    return index.patch[index.key_start[pos] : index.key_start[pos + 1]]


def _alone_in_cell(index: SpatialIndex, driving: list[bool], key: int, section: int) -> bool:
    """See :meth:`RoadLocator._alone`: the cell's patches with a driving lane all belong to
    ``section`` and are consecutive (one stretch of it, not a road crossing itself)."""
    patches = _cell_patches(index, key)
    if patches is None:
        return False
    own = []
    for patch, sec in zip(
        patches.tolist(), index.section[index.patch_lo[patches]].tolist(), strict=True
    ):
        if sec == section:
            own.append(patch)
        elif driving[sec]:
            return False
    return bool(own) and max(own) - min(own) + 1 == len(own)


class RoadLocator:
    """Road coordinates of one actor, tick after tick (see the module docstring)."""

    def __init__(self, network: RoadNetwork) -> None:
        self.network = network
        self.cursor: PathCursor | None = None
        self._road: str | None = None
        self._segment = 0
        self._s_hint = 0.0
        numbers = network.cache.setdefault("lane_numbers", {})
        assert isinstance(numbers, dict)
        self._numbers: dict[LaneRef, int | None] = numbers
        samples = network.cache.setdefault("road_samples", {})
        assert isinstance(samples, dict)
        self._samples: dict[str, _RoadSamples] = samples
        self._lanes: dict[LaneRef, Lane] = {}
        alone = network.cache.setdefault("alone_cells", {})
        assert isinstance(alone, dict)
        self._alone_cells: dict[tuple[int, int], bool] = alone
        occupied = network.cache.setdefault("occupied_cells", {})
        assert isinstance(occupied, dict)
        self._occupied_cells: dict[int, bool] = occupied

    def follow(self, path: LanePath | None) -> None:
        """Prefer ``path`` (the lanes the actor drives) from now on (None: no path)."""
        if path is None:
            self.cursor = None
        elif self.cursor is None or self.cursor.path is not path:
            self.cursor = PathCursor(path)

    def reset(self) -> None:
        """Forget where the actor was (after it was moved)."""
        self._road = None
        if self.cursor is not None:
            self.cursor.index = -1

    def locate(self, x: float, y: float, yaw: float | None = None) -> RoadPosition:
        """The actor's road coordinates at ``(x, y)`` heading ``yaw``."""
        if not (math.isfinite(x) and math.isfinite(y)):
            return OFF_MAP
        if self.cursor is not None:
            found = self._on_path(self.cursor, x, y)
            if found is not None:
                return found
        if self._road is not None:
            found = self._on_road(self._road, x, y)
            if found is not None:
                return found
        return self._search(x, y, yaw)

    # ---- the path

    def _on_path(self, cursor: PathCursor, x: float, y: float) -> RoadPosition | None:
        point = cursor.locate(x, y)
        i, a = point.index, point.fraction
        if point.distance < 0.0 or point.distance > cursor.length or not 0.0 <= a <= 1.0:
            return None
        widths = cursor.width
        width = widths[i] + a * (widths[i + 1] - widths[i])
        if abs(point.offset) > 0.5 * width:
            return None
        lane_of, ss, ts = cursor.lane_of, cursor.s, cursor.t
        table = cursor.lane_table
        if table is None:
            table = cursor.lane_table = [
                (ref, self._lane(ref), self._number(ref)) for ref in cursor.path.lanes
            ]
        lane_i, lane_j = lane_of[i], lane_of[i + 1]
        if lane_i == lane_j:
            ref, lane, number = table[lane_i]
            s = ss[i] + a * (ss[i + 1] - ss[i])
            centre = ts[i] + a * (ts[i + 1] - ts[i])
        else:  # a joint between two lanes: the nearer end's lane
            k = i if a < 0.5 else i + 1
            ref, lane, number = table[lane_of[k]]
            along = point.distance - float(cursor.path.distance[k])
            s = ss[k] + along * lane.direction
            centre = ts[k]
        self._road = ref.road
        self._segment = -1  # found from s when the road is needed
        self._s_hint = s
        return RoadPosition(
            ref.road,
            ref.section,
            ref.lane,
            s,
            centre + point.offset * lane.direction,
            point.offset,
            lane.direction,
            True,
            lane.drivable,
            number,
        )

    # ---- the last road

    def _road_samples(self, road_id: str) -> _RoadSamples:
        found = self._samples.get(road_id)
        if found is None:
            found = self._samples[road_id] = _RoadSamples(self.network, road_id)
        return found

    def _on_road(self, road_id: str, x: float, y: float) -> RoadPosition | None:
        r = self._road_samples(road_id)
        last = r.count - 2
        if last < 0:
            return None
        j = self._segment
        if j < 0:
            found = int(np.searchsorted(self.network.roads[road_id].s, self._s_hint)) - 1
            j = min(max(found, 0), last)
        a = 0.0
        t = 0.0
        h = 0.0
        for _ in range(200):
            x0, y0, h0 = r.x[j], r.y[j], r.h[j]
            dx, dy, dh = r.x[j + 1] - x0, r.y[j + 1] - y0, r.h[j + 1] - h0
            rx, ry = x - x0, y - y0
            length2 = dx * dx + dy * dy
            a = (rx * dx + ry * dy) / length2 if length2 > 0.0 else 0.0
            for _ in range(2):  # Newton on (Q - P(a)) . T(a) = 0, the heading turning linearly
                h = h0 + a * dh
                c, sn = math.cos(h), math.sin(h)
                ex, ey = rx - a * dx, ry - a * dy
                f = ex * c + ey * sn
                df = -(dx * c + dy * sn) + dh * (-ex * sn + ey * c)
                if abs(df) > 1e-12:
                    a -= f / df
            if a < 0.0 and j > 0:
                j -= 1
            elif a > 1.0 and j < last:
                j += 1
            else:
                break
        if not -1e-9 <= a <= 1.0 + 1e-9:
            return None  # beyond the road's end
        h = h0 + a * dh
        c, sn = math.cos(h), math.sin(h)
        ex, ey = rx - a * dx, ry - a * dy
        t = -ex * sn + ey * c
        section_index = r.section[j]
        road = self.network.roads[road_id]
        section = road.sections[section_index]
        k = j - section.start
        columns = r.columns[section_index]
        left_col, right_col = columns[k], columns[min(k + 1, len(columns) - 1)]
        borders = [b0 + a * (b1 - b0) for b0, b1 in zip(left_col, right_col, strict=True)]
        if not borders[-1] <= t <= borders[0]:
            return None
        slot = 0
        while slot < len(borders) - 2 and borders[slot + 1] > t:
            slot += 1
        lane = section.lanes[slot]
        self._segment = j
        s = r.s[j] + a * (r.s[j + 1] - r.s[j])
        centre = 0.5 * (borders[slot] + borders[slot + 1])
        drivable = lane.drivable or (
            not self._alone(x, y, r.first_section + section_index)
            and self._drivable_elsewhere(x, y)
        )
        return RoadPosition(
            road_id,
            section_index,
            lane.id,
            s,
            t,
            (t - centre) * lane.direction,
            lane.direction,
            True,
            drivable,
            self._number(lane.ref),
        )

    def _drivable_elsewhere(self, x: float, y: float) -> bool:
        return bool(self.network.on_drivable(np.array([x]), np.array([y]))[0])

    def _alone(self, x: float, y: float, section: int) -> bool:
        """True when, in the grid cell of ``(x, y)``, no road patch but those of ``section``
        (a global section number), near each other along it, has a driving lane: then a
        point in a lane of ``section`` that is not a driving lane is in no driving lane
        elsewhere either, and :meth:`_drivable_elsewhere` need not ask. Decided once per
        (cell, section) and kept in the network's cache."""
        key = _cell_key(self._index(), x, y)
        found = self._alone_cells.get((key, section))
        if found is None:
            found = self._alone_cells[(key, section)] = _alone_in_cell(
                self._index(), self._driving_sections(), key, section
            )
        return found

    def _occupied(self, x: float, y: float) -> bool:
        """True when some road patch lies in the grid cell of ``(x, y)`` (else the full
        projection finds no road for the point); decided once per cell."""
        key = _cell_key(self._index(), x, y)
        found = self._occupied_cells.get(key)
        if found is None:
            found = self._occupied_cells[key] = _cell_patches(self._index(), key) is not None
        return found

    def _index(self) -> SpatialIndex:
        return self.network.spatial_index()

    def _driving_sections(self) -> list[bool]:
        found = self.network.cache.get("driving_sections")
        if found is None:
            index = self._index()
            wanted = index.type_mask(DRIVING_TYPES)
            found = self.network.cache["driving_sections"] = (
                wanted[index.lane_type].any(axis=1).tolist()
            )
        assert isinstance(found, list)
        return found

    # ---- the whole map

    def _search(self, x: float, y: float, yaw: float | None) -> RoadPosition:
        if not self._occupied(x, y):
            return OFF_MAP  # no road patch in the point's cell: no road within the margin
        found = self.network.project(
            np.array([x]), np.array([y]), None if yaw is None else np.array([yaw])
        )
        point = found.point(self.network, 0)
        if point is None:  # keep the last road: the next tick tries it before searching
            return OFF_MAP
        lane = self.network.lane(point.lane)
        if point.inside:
            self._road = point.road
            self._segment = -1
            self._s_hint = point.s
        drivable = bool(found.drivable[0])
        return RoadPosition(
            point.road,
            point.lane.section,
            point.lane.lane,
            point.s,
            point.t,
            point.offset,
            lane.direction,
            point.inside,
            drivable,
            self._number(point.lane),
        )

    def _lane(self, ref: LaneRef) -> Lane:
        found = self._lanes.get(ref)
        if found is None:
            found = self._lanes[ref] = self.network.lane(ref)
        return found

    def _number(self, ref: LaneRef) -> int | None:
        if ref in self._numbers:
            return self._numbers[ref]
        lane = self.network.lane(ref)
        number = self.network.osc2_lane_index(ref) if lane.drivable else None
        self._numbers[ref] = number
        return number
