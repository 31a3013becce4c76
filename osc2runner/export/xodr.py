"""A built-in road written out as ASAM OpenDRIVE, so other players drive the same lanes.

The built-in maps (``default``, ``straight_3lane``, ``highway_4lane``, the
``Town06`` stand-in; :mod:`osc2check.world.builtin`) are one straight road
``0``, written as :func:`~osc2check.world.builtin.straight_network` builds it:
the reference line along the left edge of the carriageway in the driving
direction, right lanes ``-1 .. -n`` of the row's width (lane ``k`` counted from
the right is OpenDRIVE lane ``-(n + 1 - k)``), the row's speed limit, no links.
Lane ``-1`` gets a solid edge line on its left, the lanes between them broken
lines, the outermost a solid line: what a renderer draws.

The scenario's traffic lights placed by their pose are written as dynamic
signals of the road (``id`` the light's name, ``s``/``t`` and ``hOffset`` of its
pose: :meth:`RoadNetwork.signal_pose` gives the pose back), so a
``TrafficSignalStateAction`` can name them.

Written with scenariogeneration (``pip install "osc2-toolkit[export]"``).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence

from osc2check.world.builtin import BuiltinMap
from osc2check.world.network import RoadNetwork
from osc2runner.export.recording import LightTrack

__all__ = ["builtin_opendrive", "light_signal"]

#: OpenDRIVE's signal type of a traffic light with three bulbs (the German catalogue's
#: 1000001, which esmini and CARLA read as a traffic light)
LIGHT_TYPE, LIGHT_SUBTYPE, LIGHT_COUNTRY = "1000001", "-1", "DE"


def light_signal(network: RoadNetwork, light: LightTrack) -> tuple[float, float, str, float]:
    """``(s, t, orientation, hOffset)`` of a light's pose beside the straight road ``0`` of
    a built-in map: ``+`` when it faces traffic that drives along ``s``, the rest of its
    yaw as ``hOffset``."""
    start = network.to_world("0", 0.0, 0.0)
    dx, dy = light.x - start.x, light.y - start.y
    c, s_ = math.cos(start.yaw), math.sin(start.yaw)
    s, t = dx * c + dy * s_, -dx * s_ + dy * c
    along = _angle(light.yaw - (start.yaw + math.pi))  # facing traffic that drives along s
    if abs(along) <= 0.5 * math.pi:
        return s, t, "+", along
    return s, t, "-", _angle(light.yaw - start.yaw)


def _angle(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def builtin_opendrive(
    row: BuiltinMap, network: RoadNetwork, lights: Sequence[LightTrack], date: str
) -> ET.Element:
    """The OpenDRIVE document of a built-in map and the lights placed on it by their pose
    (see the module docstring); its header has the ``date`` given and the road's extent."""
    from scenariogeneration import xodr

    n = row.lane_count
    start = network.to_world("0", 0.0, 0.0)
    planview = xodr.PlanView(start.x, start.y, start.yaw)
    planview.add_geometry(xodr.Line(row.length))
    centre = xodr.Lane(a=0.0)
    centre.add_roadmark(xodr.RoadMark(xodr.RoadMarkType.solid, 0.15))
    section = xodr.LaneSection(0.0, centre)
    for k in range(1, n + 1):
        lane = xodr.Lane(xodr.LaneType.driving, a=row.lane_width)
        mark = xodr.RoadMarkType.solid if k == n else xodr.RoadMarkType.broken
        lane.add_roadmark(xodr.RoadMark(mark, 0.15))
        section.add_right_lane(lane)
    lanes = xodr.Lanes()
    lanes.add_lanesection(section)
    road = xodr.Road(0, planview, lanes, name=row.name)
    road.add_type(xodr.RoadType.motorway, s=0.0, speed=row.speed_limit, speed_unit="m/s")
    odr = xodr.OpenDrive(row.name, revMinor="7")
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    document: ET.Element = odr.get_element()
    header = document.find("header")
    assert header is not None
    end = network.to_world("0", row.length, -row.width)
    xs, ys = (start.x, end.x), (start.y, end.y)
    header.set("date", date)  # scenariogeneration writes the wall clock's
    extent = {"north": max(ys), "south": min(ys), "east": max(xs), "west": min(xs)}
    for key, value in extent.items():
        header.set(key, repr(float(value)))
    _signals(document, network, [light for light in lights if not light.signal])
    return document


def _signals(document: ET.Element, network: RoadNetwork, lights: Sequence[LightTrack]) -> None:
    """The lights as ``<signal>`` records of road ``0``, after its lanes (the schema's
    order). Written here, not by scenariogeneration, which keeps signal ids in one
    registry for the whole process and renames a light's signal the second time."""
    road = document.find("road")
    if not lights or road is None:
        return
    signals = ET.SubElement(road, "signals")
    for light in lights:
        s, t, orientation, h_offset = light_signal(network, light)
        ET.SubElement(
            signals,
            "signal",
            {
                "s": repr(s),
                "t": repr(t),
                "id": light.name,
                "name": light.name,
                "dynamic": "yes",
                "orientation": orientation,
                "zOffset": "2.0",
                "country": LIGHT_COUNTRY,
                "type": LIGHT_TYPE,
                "subtype": LIGHT_SUBTYPE,
                "height": "1.0",
                "width": "0.3",
                "hOffset": repr(h_offset),
            },
        )
