"""The built-in straight maps: a table of named roads, each built as a road network.

A scenario that names no map runs on ``default``; ``straight_3lane``,
``highway_4lane``, ``Town06`` and ``Town04`` (stand-ins for CARLA's maps) are the
other built-in names. Each row of :data:`BUILTIN_MAPS` is a straight, one-directional,
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
* Town06 and Town04 count scenario lanes from the left (``numbering="from_left"``),
  as CARLA numbers lanes outward from the centre line, so the design paper's
  `lane(1)` is the lane next to the median.

Both ends of the road link to nothing: driving past ``length`` is driving past
the end of the network.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from osc2check.world.errors import UnknownMapError
from osc2check.world.network import (
    Connection,
    ContactPoint,
    Junction,
    LaneRef,
    Numbering,
    RoadLink,
    RoadNetwork,
)

__all__ = [
    "BUILTIN_MAPS",
    "DEFAULT_MAP",
    "BuiltinMap",
    "builtin_lane",
    "builtin_map",
    "builtin_name",
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
    # Stand-in for CARLA's Town04, the map of most of CARLA's OSC2 examples: one
    # straight carriageway of its 4-lane highway loop (90 kph), 2000 m, lanes numbered
    # from the left as CARLA numbers them; no loop, ramps, town streets or oncoming
    # traffic, and not CARLA's world coordinates.
    "Town04": BuiltinMap(
        name="Town04",
        lane_count=4,
        length=2000.0,
        speed_limit=90.0 * _KPH,
        description="stand-in for CARLA Town04: one straight 4-lane carriageway of its "
        "highway, 2000 m; lanes numbered from the left as in CARLA",
        numbering="from_left",
    ),
}

_NETWORKS: dict[str, RoadNetwork] = {}

#: Stand-in for CARLA's Town03, for scenarios whose road must cross a junction
#: (CARLA's ``path_over_junction``): a straight town road with two lanes each way
#: (3.5 m, 60 kph) in two 600 m arms through a 30 m junction that leads straight on;
#: no side roads, curves or signals, and not CARLA's world coordinates. Lanes are
#: numbered from the left as CARLA numbers them.
TOWN03 = "Town03"
_TOWN03_ARM, _TOWN03_JUNCTION = 600.0, 30.0
_TOWN03_DESCRIPTION = (
    "stand-in for CARLA Town03: a 4-lane two-way town road (2 lanes each way) through a "
    "junction, two 600 m arms; lanes numbered from the left as in CARLA"
)


def map_names() -> tuple[str, ...]:
    """Names of the built-in maps, in table order."""
    return (*BUILTIN_MAPS, TOWN03)


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


def _is_town03(name: str) -> bool:
    return name.removesuffix(".xodr").casefold() == TOWN03.casefold()


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


def builtin_name(name: str) -> str:
    """The name a built-in map is known by (``Town06`` for ``town06.xodr``), matched as
    :func:`builtin_map` matches, the Town03 stand-in included.

    Raises:
        UnknownMapError: when no built-in map has that name.
    """
    return TOWN03 if _is_town03(name) else builtin_map(name).name


def builtin_network(name: str) -> RoadNetwork:
    """The network of the built-in map ``name`` (matched as :func:`builtin_name` does),
    built once per process and shared (networks are immutable data plus caches).

    Raises:
        UnknownMapError: when no built-in map has that name.
    """
    known = builtin_name(name)
    network = _NETWORKS.get(known)
    if network is None:
        built = town03_network() if known == TOWN03 else straight_network(BUILTIN_MAPS[known])
        network = _NETWORKS[known] = built
    return network


def town03_network() -> RoadNetwork:
    """The Town03 stand-in (see :data:`TOWN03`): roads ``1`` (west arm, x 0..600) and
    ``2`` (east arm, x 630..1230) along +x, both ways, and junction ``100`` between them,
    whose connecting roads ``101`` (eastbound) and ``102`` (westbound) lead straight on."""
    from osc2check.world.geometry import Cubic, Geometry  # as in straight_network
    from osc2check.world.layout import build_network
    from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec

    arm, gap, width = _TOWN03_ARM, _TOWN03_JUNCTION, 3.5
    limit = 60.0 * _KPH
    both_ways = (
        LaneSpec(id=-1, type="driving", widths=(Cubic(0.0, width),)),
        LaneSpec(id=-2, type="driving", widths=(Cubic(0.0, width),)),
        LaneSpec(id=1, type="driving", widths=(Cubic(0.0, width),)),
        LaneSpec(id=2, type="driving", widths=(Cubic(0.0, width),)),
    )

    def link(
        kind: Literal["road", "junction"], to: str, at: ContactPoint | None = None
    ) -> RoadLink:
        return RoadLink(kind, to, at)

    def through(pairs: tuple[tuple[int, int], ...]) -> tuple[LaneSpec, ...]:
        """Lanes -1, -2 of a connecting road, linked to the lanes ``pairs`` name."""
        return tuple(
            LaneSpec(
                id=-n,
                type="driving",
                widths=(Cubic(0.0, width),),
                predecessors=(before,),
                successors=(after,),
            )
            for n, (before, after) in enumerate(pairs, start=1)
        )

    west = RoadSpec(
        "1",
        "west",
        arm,
        None,
        (Geometry("line", 0.0, 0.0, 0.0, 0.0, arm),),
        (SectionSpec(0.0, both_ways),),
        successor=link("junction", "100"),
        speed_limit=limit,
    )
    east = RoadSpec(
        "2",
        "east",
        arm,
        None,
        (Geometry("line", 0.0, arm + gap, 0.0, 0.0, arm),),
        (SectionSpec(0.0, both_ways),),
        predecessor=link("junction", "100"),
        speed_limit=limit,
    )
    eastbound = RoadSpec(
        "101",
        "junction east",
        gap,
        "100",
        (Geometry("line", 0.0, arm, 0.0, 0.0, gap),),
        (SectionSpec(0.0, through(((-1, -1), (-2, -2)))),),
        predecessor=link("road", "1", "end"),
        successor=link("road", "2", "start"),
        speed_limit=limit,
    )
    westbound = RoadSpec(
        "102",
        "junction west",
        gap,
        "100",
        (Geometry("line", 0.0, arm + gap, 0.0, math.pi, gap),),
        (SectionSpec(0.0, through(((1, 1), (2, 2)))),),
        predecessor=link("road", "2", "start"),
        successor=link("road", "1", "end"),
        speed_limit=limit,
    )
    junction = Junction(
        "100",
        "crossing",
        (
            Connection("0", "1", "101", "start", ((-1, -1), (-2, -2))),
            Connection("1", "2", "102", "start", ((1, -1), (2, -2))),
        ),
    )
    return build_network(
        NetworkSpec(
            name=TOWN03,
            roads=(west, east, eastbound, westbound),
            junctions=(junction,),
            numbering="from_left",
            speed_limit=limit,
            description=_TOWN03_DESCRIPTION,
        )
    )


def builtin_lane(network: RoadNetwork, lane: int) -> LaneRef:
    """The lane numbered ``lane`` from the right (1 = rightmost) on a straight network."""
    count = len(network.roads["0"].sections[0].lanes)
    if not 1 <= lane <= count:
        raise ValueError(f"lane {lane} does not exist (lanes 1..{count}, 1 = rightmost)")
    return LaneRef("0", 0, -(count + 1 - lane))
