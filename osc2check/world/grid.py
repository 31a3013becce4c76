"""The grid behind world -> road projection: road patches entered in square cells.

A *patch* is a run of consecutive reference-line samples of one lane section,
at most ``PATCH_LENGTH`` long and turning at most ``PATCH_TURN``, widened
sideways to the section's outer lane borders plus ``MARGIN`` (and a little
slack for the chord's sag and the fanning normals). Each patch is a
quadrilateral; it is entered in every cell of a uniform grid it overlaps (a
separating-axis test against each cell of its bounding box, in bounded blocks
so wide roads do not take much memory). A point's cell then lists the few
patches that may contain it; :mod:`.projection` inverts the map on each.

:class:`SpatialIndex` also holds every road's samples concatenated (with a
per-section offset on ``s`` so one sorted array covers the network), lane
tables per section (ids, directions, types; padded) and the road ends that link
to nothing, for the past-the-end test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from osc2check.world.arrays import BoolArray, FloatArray, IntArray
from osc2check.world.network import RoadNetwork

__all__ = ["CELL", "MARGIN", "SpatialIndex", "build_index"]

MARGIN = 3.0  # how far outside the outer lane borders a point still gets road coordinates (m)
CELL = 1.5  # grid cell size (m)
PATCH_LENGTH = 2.0  # longest patch of the grid (m)
PATCH_TURN = 0.05  # largest heading change along a patch (rad)


@dataclass(frozen=True, eq=False)
class SpatialIndex:
    """Every road's samples concatenated, lane tables per section, and the patch grid."""

    road: IntArray  # per sample: road number
    section: IntArray  # per sample: global section number
    s: FloatArray
    x: FloatArray
    y: FloatArray
    heading: FloatArray
    borders: FloatArray  # (samples, rows): lane borders left to right, NaN-padded
    rows: IntArray  # per global section: number of border rows
    section_index: IntArray  # per global section: index within its road
    lane_id: IntArray  # (sections, lanes): OpenDRIVE ids, 0-padded
    lane_direction: IntArray  # (sections, lanes)
    lane_type: IntArray  # (sections, lanes): index into type_names, -1-padded
    type_names: tuple[str, ...]
    x0: float
    y0: float
    ny: int
    cell: float
    keys: IntArray  # sorted cell keys that hold patches
    key_start: IntArray  # patches of keys[k]: patch[key_start[k]:key_start[k + 1]]
    patch: IntArray  # patch number of each grid entry
    patch_lo: IntArray  # first sample of each patch
    patch_hi: IntArray  # last sample of each patch
    quad_x: FloatArray  # (patches, 4): corners, counter-clockwise
    quad_y: FloatArray
    quad_convex: BoolArray
    edge_x: FloatArray  # (patches, 4): corner k to corner k + 1
    edge_y: FloatArray
    key_s: FloatArray  # per sample: s plus a per-section offset, increasing over the whole index
    section_offset: FloatArray  # per global section: the offset in key_s
    margin: float
    ends: FloatArray  # dead ends: (x, y, outward heading, lateral low, high) rows

    def type_mask(self, types: frozenset[str]) -> BoolArray:
        """Per ``lane_type`` code, whether it is one of ``types``; one entry more, False,
        so that the padding code -1 indexes it."""
        return np.array([name in types for name in self.type_names] + [False])


def build_index(network: RoadNetwork, cell: float = CELL, margin: float = MARGIN) -> SpatialIndex:
    """Concatenate the roads' samples and grid their patches (see the module docstring)."""
    type_names = tuple(sorted({lane.type for lane in network.lanes()}))
    type_code = {name: i for i, name in enumerate(type_names)}
    sections = [sec for road in network.roads.values() for sec in road.sections]
    max_lanes = max(len(sec.lanes) for sec in sections)
    lane_id = np.zeros((len(sections), max(max_lanes, 1)), dtype=np.int64)
    lane_direction = np.zeros_like(lane_id)
    lane_type = np.full_like(lane_id, -1)
    rows = np.zeros(len(sections), dtype=np.int64)
    section_index = np.zeros(len(sections), dtype=np.int64)
    parts: dict[str, list[FloatArray]] = {k: [] for k in ("s", "x", "y", "heading")}
    road_of: list[IntArray] = []
    section_of: list[IntArray] = []
    border_parts: list[FloatArray] = []
    g = 0
    for number, road in enumerate(network.roads.values()):
        for sec in road.sections:
            n = sec.stop - sec.start
            sl = slice(sec.start, sec.stop)
            for key, values in (
                ("s", road.s),
                ("x", road.x),
                ("y", road.y),
                ("heading", road.heading),
            ):
                parts[key].append(values[sl])
            road_of.append(np.full(n, number, dtype=np.int64))
            section_of.append(np.full(n, g, dtype=np.int64))
            padded = np.full((n, max_lanes + 1), np.nan)
            padded[:, : sec.borders.shape[0]] = sec.borders.T
            border_parts.append(padded)
            rows[g] = sec.borders.shape[0]
            section_index[g] = sec.index
            for k, lane in enumerate(sec.lanes):
                lane_id[g, k] = lane.id
                lane_direction[g, k] = lane.direction
                lane_type[g, k] = type_code[lane.type]
            g += 1
    s = np.concatenate(parts["s"])
    x = np.concatenate(parts["x"])
    y = np.concatenate(parts["y"])
    heading = np.concatenate(parts["heading"])
    road_number = np.concatenate(road_of)
    section = np.concatenate(section_of)
    borders = np.concatenate(border_parts)
    lengths = np.array([sec.s1 + 1.0 for sec in sections])
    section_offset = np.concatenate(([0.0], np.cumsum(lengths)[:-1]))

    # Patches: runs of samples inside one section, at most PATCH_LENGTH long and
    # turning at most PATCH_TURN, so a patch holds a few samples even on tight curves.
    n_samples = len(s)
    section_first = np.concatenate(([True], section[1:] != section[:-1]))
    section_last = np.concatenate((section[1:] != section[:-1], [True]))
    bucket = np.floor(s / PATCH_LENGTH) + 1e6 * np.floor(heading / PATCH_TURN)
    changed = np.concatenate(([True], bucket[1:] != bucket[:-1]))
    nodes = np.flatnonzero(section_first | section_last | changed)
    lo_all, hi_all = nodes[:-1], nodes[1:]
    valid = (section[lo_all] == section[hi_all]) & (s[hi_all] > s[lo_all])
    patch_lo, patch_hi = lo_all[valid], hi_all[valid]
    with np.errstate(invalid="ignore"):
        t_high = np.nanmax(borders, axis=1)
        t_low = np.nanmin(borders, axis=1)
    # Widest border and largest distance from the chord over each patch's samples.
    owner_of = np.clip(np.searchsorted(patch_lo, np.arange(n_samples), side="right") - 1, 0, None)
    cx_, cy_ = x[patch_hi] - x[patch_lo], y[patch_hi] - y[patch_lo]
    chord = np.hypot(cx_, cy_)
    o = owner_of
    sag = np.abs((x - x[patch_lo[o]]) * cy_[o] - (y - y[patch_lo[o]]) * cx_[o]) / chord[o]
    hi = np.maximum.reduceat(t_high, patch_lo)[: len(patch_lo)]
    lo = np.minimum.reduceat(t_low, patch_lo)[: len(patch_lo)]
    sag_max = np.maximum.reduceat(sag, patch_lo)[: len(patch_lo)]
    hi = np.maximum(hi, t_high[patch_hi]) + margin
    lo = np.minimum(lo, t_low[patch_hi]) - margin
    turn = np.abs(heading[patch_hi] - heading[patch_lo])
    slack = 0.01 + sag_max + turn * np.maximum(np.abs(hi), np.abs(lo))
    hi = hi + slack
    lo = lo - slack
    first, last = patch_lo, patch_hi
    corners_x = np.stack(
        [
            x[first] - lo * np.sin(heading[first]),
            x[last] - lo * np.sin(heading[last]),
            x[last] - hi * np.sin(heading[last]),
            x[first] - hi * np.sin(heading[first]),
        ],
        axis=1,
    )
    corners_y = np.stack(
        [
            y[first] + lo * np.cos(heading[first]),
            y[last] + lo * np.cos(heading[last]),
            y[last] + hi * np.cos(heading[last]),
            y[first] + hi * np.cos(heading[first]),
        ],
        axis=1,
    )
    x0 = float(corners_x.min()) - cell
    y0 = float(corners_y.min()) - cell
    ny = int((corners_y.max() - y0) // cell) + 2
    ix0 = ((corners_x.min(axis=1) - x0) // cell).astype(np.int64)
    ix1 = ((corners_x.max(axis=1) - x0) // cell).astype(np.int64)
    iy0 = ((corners_y.min(axis=1) - y0) // cell).astype(np.int64)
    iy1 = ((corners_y.max(axis=1) - y0) // cell).astype(np.int64)
    wx = ix1 - ix0 + 1
    wy = iy1 - iy0 + 1
    counts = wx * wy
    key_parts: list[IntArray] = []
    patch_parts: list[IntArray] = []
    # Enumerate (patch, cell) candidates in blocks to bound memory on wide roads.
    bounds = np.searchsorted(np.cumsum(counts), np.arange(0, int(counts.sum()), 65536))
    for lo_p, hi_p in zip(bounds, [*bounds[1:], len(counts)], strict=True):
        block = np.arange(lo_p, hi_p)
        if len(block) == 0:
            continue
        c = counts[block]
        owner = np.repeat(block, c)
        local = np.arange(int(c.sum())) - np.repeat(np.cumsum(c) - c, c)
        cx = ix0[owner] + local // wy[owner]
        cy = iy0[owner] + local % wy[owner]
        keep = _patch_overlaps_cell(
            corners_x[owner], corners_y[owner], x0 + cx * cell, y0 + cy * cell, cell
        )
        key_parts.append((cx * ny + cy)[keep])
        patch_parts.append(owner[keep])
    keys_all = np.concatenate(key_parts)
    patch_all = np.concatenate(patch_parts)
    order = np.argsort(keys_all, kind="stable")
    keys_sorted = keys_all[order]
    keys, key_first = np.unique(keys_sorted, return_index=True)
    key_start = np.append(key_first, len(keys_sorted)).astype(np.int64)
    return SpatialIndex(
        road=road_number,
        section=section,
        s=s,
        x=x,
        y=y,
        heading=heading,
        borders=borders,
        rows=rows,
        section_index=section_index,
        lane_id=lane_id,
        lane_direction=lane_direction,
        lane_type=lane_type,
        type_names=type_names,
        x0=x0,
        y0=y0,
        ny=ny,
        cell=cell,
        keys=keys.astype(np.int64),
        key_start=key_start,
        patch=patch_all[order].astype(np.int64),
        patch_lo=patch_lo.astype(np.int64),
        patch_hi=patch_hi.astype(np.int64),
        quad_x=corners_x,
        quad_y=corners_y,
        quad_convex=_convex(corners_x, corners_y),
        edge_x=np.roll(corners_x, -1, axis=1) - corners_x,
        edge_y=np.roll(corners_y, -1, axis=1) - corners_y,
        key_s=s + section_offset[section],
        section_offset=section_offset,
        margin=margin,
        ends=_dead_ends(network),
    )


def _patch_overlaps_cell(
    qx: FloatArray, qy: FloatArray, cx: FloatArray, cy: FloatArray, cell: float
) -> BoolArray:
    """Separating-axis test of quadrilaterals (rows of 4 corners) against square cells.

    The cell axes are covered by the bounding-box enumeration; the quad's edge
    normals are tested here. A quad that is not convex (a patch folded on the
    inside of a very tight curve) is kept whenever its bounding box overlaps.
    """
    half = 0.5 * cell
    mx = cx + half
    my = cy + half
    ex = np.roll(qx, -1, axis=1) - qx
    ey = np.roll(qy, -1, axis=1) - qy
    convex = _convex(qx, qy)
    overlap = np.ones(len(qx), dtype=bool)
    for k in range(4):
        nx = -ey[:, k]
        ny = ex[:, k]
        proj = qx * nx[:, None] + qy * ny[:, None]
        lo = proj.min(axis=1)
        hi = proj.max(axis=1)
        centre = mx * nx + my * ny
        radius = half * (np.abs(nx) + np.abs(ny))
        overlap &= (centre + radius >= lo) & (centre - radius <= hi)
    result: BoolArray = overlap | ~convex
    return result


def _convex(qx: FloatArray, qy: FloatArray) -> BoolArray:
    """True for rows of 4 corners that form a counter-clockwise convex quadrilateral."""
    ex = np.roll(qx, -1, axis=1) - qx
    ey = np.roll(qy, -1, axis=1) - qy
    cross = ex * np.roll(ey, -1, axis=1) - ey * np.roll(ex, -1, axis=1)
    result: BoolArray = np.all(cross >= 0.0, axis=1)
    return result


def _dead_ends(network: RoadNetwork) -> FloatArray:
    """Road ends that link to nothing: ``(x, y, outward heading, t_low, t_high)`` rows."""
    rows = []
    for road in network.roads.values():
        for link, i, section, flip in (
            (road.predecessor, 0, road.sections[0], math.pi),
            (road.successor, len(road.s) - 1, road.sections[-1], 0.0),
        ):
            if link is not None:
                continue
            column = 0 if i == 0 else -1
            low, high = float(section.borders[-1, column]), float(section.borders[0, column])
            if flip:  # looking out of the road's start, its left side is on the right
                low, high = -high, -low
            rows.append(
                (float(road.x[i]), float(road.y[i]), float(road.heading[i]) + flip, low, high)
            )
    return np.array(rows, dtype=np.float64).reshape(-1, 5)
