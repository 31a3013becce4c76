"""The built-in straight maps (:mod:`osc2check.road`) as road networks.

Each named map of :mod:`osc2check.road` (``default``, ``straight_3lane``,
``highway_4lane``, ``Town06``) becomes a one-road network with the same
dimensions, read from the same :class:`osc2check.road.Road` rows, so there is
one table of sizes. The road is written as OpenDRIVE would write it and goes
through the same layout step as a file:

* The reference line runs along the left edge of the carriageway in the
  driving direction (``y = width`` heading +x for ``direction=+1``, ``y = 0``
  heading -x for ``direction=-1``), so ``s`` is the built-in road's ``s``.
* The lanes are right lanes ``-1 .. -n`` under right-hand traffic; built-in
  lane ``k`` (1 = rightmost) is OpenDRIVE lane ``-(n + 1 - k)``.
* Town06 counts scenario lanes from the left (``numbering="from_left"``).

Both ends of the road link to nothing: driving past ``length`` is driving past
the end of the network.
"""

from __future__ import annotations

import math

from osc2check.road import Road as StraightRoad
from osc2check.road import get_map
from osc2check.world.geometry import Cubic, Geometry
from osc2check.world.layout import build_network
from osc2check.world.network import LaneRef, Numbering, RoadNetwork
from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec

__all__ = ["builtin_lane", "builtin_network", "straight_network"]


def straight_network(road: StraightRoad) -> RoadNetwork:
    """The road network of one built-in straight road."""
    n = road.lane_count
    if road.direction == 1:
        geometry = Geometry("line", 0.0, 0.0, road.width, 0.0, road.length)
    else:
        geometry = Geometry("line", 0.0, road.length, 0.0, math.pi, road.length)
    lanes = tuple(
        LaneSpec(id=-j, type="driving", widths=(Cubic(0.0, road.lane_width),))
        for j in range(1, n + 1)
    )
    spec = RoadSpec(
        id="0",
        name=road.name,
        length=road.length,
        junction=None,
        geometries=(geometry,),
        sections=(SectionSpec(0.0, lanes),),
        speed_limit=road.speed_limit,
    )
    numbering: Numbering = "from_left" if road.numbering == "from_left" else "from_right"
    return build_network(
        NetworkSpec(
            name=road.name,
            roads=(spec,),
            numbering=numbering,
            speed_limit=road.speed_limit,
            description=road.description,
        )
    )


def builtin_network(name: str) -> RoadNetwork:
    """The network of the built-in map ``name`` (matched as :func:`osc2check.road.get_map` does).

    Raises:
        UnknownMapError: when no built-in map has that name.
    """
    return straight_network(get_map(name))


def builtin_lane(network: RoadNetwork, lane: int) -> LaneRef:
    """The lane that built-in lane number ``lane`` (1 = rightmost) names on a straight network."""
    count = len(network.roads["0"].sections[0].lanes)
    if not 1 <= lane <= count:
        raise ValueError(f"lane {lane} does not exist (lanes 1..{count}, 1 = rightmost)")
    return LaneRef("0", 0, -(count + 1 - lane))
