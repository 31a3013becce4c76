"""The built-in straight maps: a table of named roads, each built as a road network.

A scenario that names no map runs on ``default``; ``straight_3lane``,
``highway_4lane`` and ``Town06`` (a stand-in for CARLA's Town06) are the other
built-in names. Each row of :data:`BUILTIN_MAPS` is a straight, one-directional,
multi-lane road; :func:`straight_network` writes it as OpenDRIVE would and sends
it through the same layout step as a file, so a built-in map is a
:class:`~osc2check.world.network.RoadNetwork` like any other:

* The reference line runs along the left edge of the carriageway in the
  driving direction (``y = width`` heading +x for ``direction=+1``, ``y = 0``
  heading -x for ``direction=-1``): the world frame has x along the road and
  y to the left, the road covers ``0 <= x <= length``, ``0 <= y <= width``,
  and ``s`` is the distance from the road's entry.
* The lanes are right lanes ``-1 .. -n`` under right-hand traffic; lane ``k``
  counted from the right (1 = rightmost) is OpenDRIVE lane ``-(n + 1 - k)``
  (:func:`builtin_lane`).
* Town06 counts scenario lanes from the left (``numbering="from_left"``), as
  CARLA numbers lanes outward from the centre line, so the design paper's
  `lane(1)` is the lane next to the median.

Both ends of the road link to nothing: driving past ``length`` is driving past
the end of the network.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from osc2check.world.errors import UnknownMapError
from osc2check.world.network import LaneRef, Numbering, RoadNetwork

__all__ = [
    "BUILTIN_MAPS",
    "DEFAULT_MAP",
    "BuiltinMap",
    "builtin_lane",
    "builtin_map",
    "builtin_network",
    "map_names",
    "straight_network",
]

DEFAULT_MAP = "default"
_KPH = 1.0 / 3.6


@dataclass(frozen=True, slots=True)
class BuiltinMap:
    """A straight one-directional multi-lane road (one row of the built-in maps).

    Parameters:
        name: the map name.
        lane_count: number of driving lanes (>= 1).
        lane_width: width of every lane in metres.
        length: length of the road in metres.
        direction: +1 when traffic drives towards +x, -1 towards -x.
        speed_limit: legal speed limit in m/s, or None when unknown.
        description: one line for humans (shown by tools listing maps).
        numbering: how scenarios number its lanes: ``from_right`` or ``from_left``.
    """

    name: str
    lane_count: int = 3
    lane_width: float = 3.5
    length: float = 1000.0
    direction: int = 1
    speed_limit: float | None = None
    description: str = ""
    numbering: Numbering = "from_right"

    def __post_init__(self) -> None:
        if self.lane_count < 1:
            raise ValueError(f"lane_count must be >= 1, got {self.lane_count}")
        if self.lane_width <= 0.0:
            raise ValueError(f"lane_width must be > 0, got {self.lane_width}")
        if self.length <= 0.0:
            raise ValueError(f"length must be > 0, got {self.length}")
        if self.direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {self.direction}")

    @property
    def width(self) -> float:
        """Total width of the driving lanes in metres."""
        return self.lane_count * self.lane_width


BUILTIN_MAPS: dict[str, BuiltinMap] = {
    "default": BuiltinMap(
        name="default",
        speed_limit=130.0 * _KPH,
        description="straight road, 3 lanes of 3.5 m, 1000 m",
    ),
    "straight_3lane": BuiltinMap(
        name="straight_3lane",
        speed_limit=130.0 * _KPH,
        description="straight road, 3 lanes of 3.5 m, 1000 m",
    ),
    "highway_4lane": BuiltinMap(
        name="highway_4lane",
        lane_count=4,
        length=2000.0,
        speed_limit=130.0 * _KPH,
        description="straight highway, 4 lanes of 3.5 m, 2000 m",
    ),
    # Stand-in for CARLA's Town06: its main feature is long straight highway
    # sections with several lanes per direction. Only one carriageway of such
    # a straight section is modelled (4 lanes, 1500 m, 90 kph signs); there
    # are no curves, ramps, junctions or oncoming traffic.
    "Town06": BuiltinMap(
        name="Town06",
        lane_count=4,
        length=1500.0,
        speed_limit=90.0 * _KPH,
        description="stand-in for CARLA Town06: one straight 4-lane carriageway, 1500 m; "
        "lanes numbered from the left as in CARLA",
        numbering="from_left",
    ),
}

_NETWORKS: dict[str, RoadNetwork] = {}


def map_names() -> tuple[str, ...]:
    """Names of the built-in maps, in table order."""
    return tuple(BUILTIN_MAPS)


def builtin_map(name: str) -> BuiltinMap:
    """The built-in map called ``name``.

    Names are matched exactly first, then case-insensitively, and a trailing
    ``.xodr`` is ignored (``"Town06.xodr"`` finds the Town06 stand-in).

    Raises:
        UnknownMapError: when no built-in map has that name; the message lists the
        known names.
    """
    if name in BUILTIN_MAPS:
        return BUILTIN_MAPS[name]
    key = name.removesuffix(".xodr").casefold()
    for known, row in BUILTIN_MAPS.items():
        if known.casefold() == key:
            return row
    raise UnknownMapError(name, map_names())


def straight_network(row: BuiltinMap) -> RoadNetwork:
    """The road network of one straight road."""
    # the geometry needs numpy, which a check on a cached map never imports
    from osc2check.world.geometry import Cubic, Geometry
    from osc2check.world.layout import build_network
    from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec

    n = row.lane_count
    if row.direction == 1:
        geometry = Geometry("line", 0.0, 0.0, row.width, 0.0, row.length)
    else:
        geometry = Geometry("line", 0.0, row.length, 0.0, math.pi, row.length)
    lanes = tuple(
        LaneSpec(id=-j, type="driving", widths=(Cubic(0.0, row.lane_width),))
        for j in range(1, n + 1)
    )
    spec = RoadSpec(
        id="0",
        name=row.name,
        length=row.length,
        junction=None,
        geometries=(geometry,),
        sections=(SectionSpec(0.0, lanes),),
        speed_limit=row.speed_limit,
    )
    return build_network(
        NetworkSpec(
            name=row.name,
            roads=(spec,),
            numbering=row.numbering,
            speed_limit=row.speed_limit,
            description=row.description,
        )
    )


def builtin_network(name: str) -> RoadNetwork:
    """The network of the built-in map ``name`` (matched as :func:`builtin_map` does),
    built once per process and shared (networks are immutable data plus caches).

    Raises:
        UnknownMapError: when no built-in map has that name.
    """
    row = builtin_map(name)
    network = _NETWORKS.get(row.name)
    if network is None:
        network = _NETWORKS[row.name] = straight_network(row)
    return network


def builtin_lane(network: RoadNetwork, lane: int) -> LaneRef:
    """The lane numbered ``lane`` from the right (1 = rightmost) on a straight network."""
    count = len(network.roads["0"].sections[0].lanes)
    if not 1 <= lane <= count:
        raise ValueError(f"lane {lane} does not exist (lanes 1..{count}, 1 = rightmost)")
    return LaneRef("0", 0, -(count + 1 - lane))
