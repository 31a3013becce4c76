"""The built-in road model shared by the checker and the runner.

A road here is plain data: a straight, one-directional, multi-lane road. The
checker places actors on it (initial placement, lane counts) and the runner
builds its MuJoCo world on it, so both agree on where every lane lies. No
simulation code is imported here.

Frames and conventions
----------------------

* **World frame**: x along the road, y to the left of the +x direction, z up
  (right-handed). The road covers ``0 <= x <= length`` and
  ``0 <= y <= lane_count * lane_width``.
* **Driving direction**: ``direction = +1`` means traffic drives towards +x,
  ``-1`` towards -x. The road heading (yaw of a vehicle driving along the
  lanes) is 0 or pi accordingly.
* **Road frame** ``(s, t)``: ``s`` is the distance along the driving direction
  from the start of the road (0 at the entry, ``length`` at the exit); ``t``
  is the lateral offset to the *left* of the driving direction, measured from
  the right edge of the road.
* **Lane numbering**: internally (``lane_center_y``, ``lane_of``, ...) lane 1 is
  the rightmost lane in the driving direction and numbers grow to the left, up
  to ``lane_count``. That is also how scenarios count lanes on most maps (the
  standard's `lane()` counts from the right by default). A map may count the
  scenario's lane numbers from the left instead (``numbering="from_left"``):
  the Town06 stand-in does, as CARLA numbers lanes outward from the centre
  line, so the design paper's `lane(1)` is the lane next to the median and
  "one lane to the right of it" exists. ``to_scenario_lane`` converts.

OpenDRIVE maps are a later extension behind the same interface
(``lane_center_y``, ``lane_of``, ``to_xy``, ``to_st``, ``bounds``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "Road",
    "UnknownMapError",
    "get_map",
    "map_names",
]


@dataclass(frozen=True, slots=True)
class Road:
    """A straight one-directional multi-lane road.

    Parameters:
        name: the map name the road was built from.
        lane_count: number of driving lanes (>= 1).
        lane_width: width of every lane in metres (3.5 m by default).
        length: length of the road in metres.
        direction: +1 when traffic drives towards +x, -1 towards -x.
        speed_limit: legal speed limit in m/s, or None when unknown.
        description: one line for humans (shown by tools listing maps).
    """

    name: str = "default"
    lane_count: int = 3
    lane_width: float = 3.5
    length: float = 1000.0
    direction: int = 1
    speed_limit: float | None = None
    description: str = ""
    numbering: str = "from_right"  # how scenarios number lanes: "from_right" | "from_left"

    def __post_init__(self) -> None:
        if self.lane_count < 1:
            raise ValueError(f"lane_count must be >= 1, got {self.lane_count}")
        if self.lane_width <= 0.0:
            raise ValueError(f"lane_width must be > 0, got {self.lane_width}")
        if self.length <= 0.0:
            raise ValueError(f"length must be > 0, got {self.length}")
        if self.direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {self.direction}")

    # ------------------------------------------------------------------ geometry

    @property
    def width(self) -> float:
        """Total width of the driving lanes in metres."""
        return self.lane_count * self.lane_width

    @property
    def heading(self) -> float:
        """Yaw (rad) of the driving direction in the world frame: 0 or pi."""
        return 0.0 if self.direction == 1 else math.pi

    def bounds(self) -> tuple[float, float, float, float]:
        """The road surface as ``(x_min, x_max, y_min, y_max)`` in the world frame."""
        return (0.0, self.length, 0.0, self.width)

    def has_lane(self, lane: int) -> bool:
        """True when ``lane`` is a valid lane number (1 .. lane_count)."""
        return 1 <= lane <= self.lane_count

    def to_scenario_lane(self, lane: int) -> int:
        """The scenario's number for internal lane ``lane`` (the inverse of the above)."""
        return self.lane_count + 1 - lane if self.numbering == "from_left" else lane

    def lane_center_t(self, lane: int) -> float:
        """Lateral road coordinate ``t`` of the centre of ``lane``."""
        self._require_lane(lane)
        return (lane - 0.5) * self.lane_width

    def lane_center_y(self, lane: int) -> float:
        """World y of the centre line of ``lane`` (1 = rightmost in driving direction)."""
        return self._t_to_y(self.lane_center_t(lane))

    def lane_of(self, y: float) -> int | None:
        """The lane containing world coordinate ``y``, or None when off the road.

        A point exactly on a lane boundary belongs to the lane on its left
        (the higher number), except on the left road edge.
        """
        t = self._y_to_t(y)
        if t < 0.0 or t > self.width:
            return None
        return min(int(t // self.lane_width) + 1, self.lane_count)

    def lane_offset(self, y: float) -> float | None:
        """Lateral offset (m, positive to the left) of ``y`` from its lane centre."""
        lane = self.lane_of(y)
        if lane is None:
            return None
        return self._y_to_t(y) - self.lane_center_t(lane)

    def to_xy(self, s: float, t: float) -> tuple[float, float]:
        """Road coordinates ``(s, t)`` to world ``(x, y)``."""
        x = s if self.direction == 1 else self.length - s
        return (x, self._t_to_y(t))

    def to_st(self, x: float, y: float) -> tuple[float, float]:
        """World ``(x, y)`` to road coordinates ``(s, t)``."""
        s = x if self.direction == 1 else self.length - x
        return (s, self._y_to_t(y))

    def lane_to_xy(self, s: float, lane: int, offset: float = 0.0) -> tuple[float, float]:
        """World ``(x, y)`` of the point ``s`` along ``lane``, ``offset`` m to its left."""
        return self.to_xy(s, self.lane_center_t(lane) + offset)

    def contains(self, x: float, y: float) -> bool:
        """True when the world point lies on the road surface."""
        x0, x1, y0, y1 = self.bounds()
        return x0 <= x <= x1 and y0 <= y <= y1

    # ------------------------------------------------------------------ helpers

    def _t_to_y(self, t: float) -> float:
        return t if self.direction == 1 else self.width - t

    def _y_to_t(self, y: float) -> float:
        return y if self.direction == 1 else self.width - y

    def _require_lane(self, lane: int) -> None:
        if not self.has_lane(lane):
            raise ValueError(
                f"lane {lane} does not exist on map `{self.name}` "
                f"(lanes 1..{self.lane_count}, 1 = rightmost in driving direction)"
            )


class UnknownMapError(LookupError):
    """Raised by :func:`get_map` for a name that is not a built-in map."""

    def __init__(self, name: str, known: tuple[str, ...]) -> None:
        self.name = name
        self.known = known
        super().__init__(f"unknown map `{name}`; known built-in maps: {', '.join(known)}")


_KPH = 1.0 / 3.6

_MAPS: dict[str, Road] = {
    "default": Road(
        name="default",
        lane_count=3,
        lane_width=3.5,
        length=1000.0,
        speed_limit=130.0 * _KPH,
        description="straight road, 3 lanes of 3.5 m, 1000 m",
    ),
    "straight_3lane": Road(
        name="straight_3lane",
        lane_count=3,
        lane_width=3.5,
        length=1000.0,
        speed_limit=130.0 * _KPH,
        description="straight road, 3 lanes of 3.5 m, 1000 m",
    ),
    "highway_4lane": Road(
        name="highway_4lane",
        lane_count=4,
        lane_width=3.5,
        length=2000.0,
        speed_limit=130.0 * _KPH,
        description="straight highway, 4 lanes of 3.5 m, 2000 m",
    ),
    # Stand-in for CARLA's Town06: its main feature is long straight highway
    # sections with several lanes per direction. Only one carriageway of such
    # a straight section is modelled (4 lanes, 1500 m, 90 kph signs); there
    # are no curves, ramps, junctions or oncoming traffic.
    "Town06": Road(
        name="Town06",
        lane_count=4,
        lane_width=3.5,
        length=1500.0,
        speed_limit=90.0 * _KPH,
        description="stand-in for CARLA Town06: one straight 4-lane carriageway, 1500 m; "
        "lanes numbered from the left as in CARLA",
        numbering="from_left",
    ),
}


def map_names() -> tuple[str, ...]:
    """Names of the built-in maps, in registry order."""
    return tuple(_MAPS)


def get_map(name: str) -> Road:
    """The built-in map called ``name``.

    Names are matched exactly first, then case-insensitively, and a trailing
    ``.xodr`` is ignored (``"Town06.xodr"`` finds the Town06 stand-in).

    Raises:
        UnknownMapError: when no built-in map has that name; the message lists
        the known names.
    """
    if name in _MAPS:
        return _MAPS[name]
    key = name.removesuffix(".xodr").casefold()
    for known, road in _MAPS.items():
        if known.casefold() == key:
            return road
    raise UnknownMapError(name, map_names())
