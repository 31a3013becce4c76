"""Write the bundled OpenDRIVE maps of this folder.

    python examples/maps/make_maps.py            # rewrite the .xodr files beside this script
    python examples/maps/make_maps.py OUT_DIR    # write them elsewhere (tests compare)

* ``rural_curves.xodr``: a two-lane rural road (one lane per direction, 3.5 m,
  with 1 m shoulders), 70 km/h: lines, clothoids, a left-hand arc of radius
  100 m and 300 m (20 s at 50 km/h is 278 m), then a right-hand clothoid-arc-
  clothoid bend of radius 150 m. A speed-limit sign at the start.
* ``four_way_junction.xodr``: four 200 m arms (one lane per direction, 3.5 m,
  2 m sidewalks) meeting in a junction 30 m across. Each arm's incoming lane
  has three connecting roads, straight, left and right; the turns are
  clothoid-arc-clothoid curves fitted to the corner. A traffic light on each
  arm, two controllers (north-south, east-west).

The maps are written by hand with the standard library's ElementTree, each
geometry record's start pose computed with the toolkit's own geometry
evaluation so consecutive records meet exactly. (scenariogeneration can write
such maps, but it writes arcs as spirals with ``curvStart="1e-09"``, carries
both directions on every connecting road and needs lxml, xmlschema, SciPy and
a compiled clothoid library; these two maps need neither.)
"""

from __future__ import annotations

import math
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from osc2check.world.geometry import Geometry, evaluate

LANE = 3.5
JUNCTION_HALF = 15.0  # distance from the junction centre to where the arms end (m)
ARM = 200.0


@dataclass(frozen=True)
class Piece:
    """A geometry record before its start pose is known."""

    kind: str
    length: float
    curvature: float = 0.0
    curv_start: float = 0.0
    curv_end: float = 0.0


def chain(x: float, y: float, hdg: float, pieces: list[Piece]) -> list[Geometry]:
    """Geometry records one after another from the pose ``(x, y, hdg)``."""
    records = []
    s = 0.0
    for piece in pieces:
        g = Geometry(
            piece.kind,  # type: ignore[arg-type]
            s,
            x,
            y,
            hdg,
            piece.length,
            curvature=piece.curvature,
            curv_start=piece.curv_start,
            curv_end=piece.curv_end,
        )
        records.append(g)
        end = evaluate(g, np.array([piece.length]))
        x, y, hdg = float(end.x[0]), float(end.y[0]), float(end.heading[0])
        s += piece.length
    return records


def num(value: float) -> str:
    """A number as OpenDRIVE text: shortest round-tripping form, no ``-0``."""
    value = 0.0 if value == 0 else value
    return repr(round(value, 12))


def sub(parent: ET.Element, tag: str, **attrib: str | float | int) -> ET.Element:
    text = {
        k.rstrip("_"): v if isinstance(v, str) else num(v) if isinstance(v, float) else str(v)
        for k, v in attrib.items()
    }
    return ET.SubElement(parent, tag, text)


def document(name: str) -> ET.Element:
    root = ET.Element("OpenDRIVE")
    sub(
        root,
        "header",
        revMajor=1,
        revMinor=8,
        name=name,
        version="1.0",
        vendor="osc2 toolkit",
        north=0.0,
        south=0.0,
        east=0.0,
        west=0.0,
    )
    return root


def plan_view(road: ET.Element, records: list[Geometry]) -> None:
    plan = sub(road, "planView")
    for g in records:
        geometry = sub(plan, "geometry", s=g.s, x=g.x, y=g.y, hdg=g.hdg, length=g.length)
        match g.kind:
            case "line":
                sub(geometry, "line")
            case "arc":
                sub(geometry, "arc", curvature=g.curvature)
            case "spiral":
                sub(geometry, "spiral", curvStart=g.curv_start, curvEnd=g.curv_end)


def lane(
    parent: ET.Element,
    lane_id: int,
    kind: str,
    width: float,
    predecessor: int | None = None,
    successor: int | None = None,
) -> None:
    element = sub(parent, "lane", id=lane_id, type=kind, level="false")
    if predecessor is not None or successor is not None:
        link = sub(element, "link")
        if predecessor is not None:
            sub(link, "predecessor", id=predecessor)
        if successor is not None:
            sub(link, "successor", id=successor)
    sub(element, "width", sOffset=0.0, a=width, b=0.0, c=0.0, d=0.0)


def two_way_lanes(road: ET.Element, outer: str, outer_width: float) -> None:
    section = sub(sub(road, "lanes"), "laneSection", s=0.0)
    left = sub(section, "left")
    lane(left, 2, outer, outer_width)
    lane(left, 1, "driving", LANE)
    sub(sub(section, "center"), "lane", id=0, type="none", level="false")
    right = sub(section, "right")
    lane(right, -1, "driving", LANE)
    lane(right, -2, outer, outer_width)


# ---------------------------------------------------------------- rural road


def rural_curves() -> ET.Element:
    root = document("rural_curves")
    pieces = [
        Piece("line", 100.0),
        Piece("spiral", 50.0, curv_start=0.0, curv_end=0.01),
        Piece("arc", 300.0, curvature=0.01),
        Piece("spiral", 50.0, curv_start=0.01, curv_end=0.0),
        Piece("line", 100.0),
        Piece("spiral", 40.0, curv_start=0.0, curv_end=-1.0 / 150.0),
        Piece("arc", 150.0, curvature=-1.0 / 150.0),
        Piece("spiral", 40.0, curv_start=-1.0 / 150.0, curv_end=0.0),
        Piece("line", 150.0),
    ]
    records = chain(0.0, 0.0, 0.0, pieces)
    length = sum(p.length for p in pieces)
    road = sub(root, "road", name="rural curves", length=length, id="1", junction="-1", rule="RHT")
    sub(road, "link")
    road_type = sub(road, "type", s=0.0, type="rural")
    sub(road_type, "speed", max="70", unit="km/h")
    plan_view(road, records)
    sub(sub(road, "elevationProfile"), "elevation", s=0.0, a=0.0, b=0.0, c=0.0, d=0.0)
    two_way_lanes(road, "shoulder", 1.0)
    signals = sub(road, "signals")
    sub(
        signals,
        "signal",
        s=10.0,
        t=-5.0,
        id="1",
        name="speed limit 70",
        dynamic="no",
        orientation="+",
        zOffset=1.5,
        country="DE",
        type="274",
        subtype="57",
        value=70.0,
        unit="km/h",
        height=0.6,
        width=0.6,
    )
    return root


# ---------------------------------------------------------------- four-way junction


def turn_pieces(sign: float) -> list[Piece]:
    """Clothoid-arc-clothoid turning 90 degrees (left for ``sign=+1``) from the end of one
    arm to the start of the next: its start and end tangents meet at the junction centre,
    JUNCTION_HALF from both ends. Each clothoid turns 15 degrees."""

    def pieces(radius: float) -> list[Piece]:
        spiral = radius * math.radians(30.0)  # turns spiral / (2 radius) = 15 degrees
        arc = radius * math.radians(60.0)
        k = sign / radius
        return [
            Piece("spiral", spiral, curv_start=0.0, curv_end=k),
            Piece("arc", arc, curvature=k),
            Piece("spiral", spiral, curv_start=k, curv_end=0.0),
        ]

    def overshoot(radius: float) -> float:
        # From (0, 0) heading 0 the end should lie on the line x = JUNCTION_HALF.
        end = chain(0.0, 0.0, 0.0, pieces(radius))[-1]
        tail = evaluate(end, np.array([end.length]))
        return float(tail.x[0]) - JUNCTION_HALF

    low, high = 1.0, 2.0 * JUNCTION_HALF
    for _ in range(100):
        mid = 0.5 * (low + high)
        if overshoot(mid) > 0.0:
            high = mid
        else:
            low = mid
    return pieces(0.5 * (low + high))


def four_way_junction() -> ET.Element:
    root = document("four_way_junction")
    arms = {"1": 0.0, "2": 90.0, "3": 180.0, "4": 270.0}  # arm id -> direction from the centre
    junction_id = "100"
    connections: list[tuple[str, str]] = []
    for arm_id, angle in arms.items():
        a = math.radians(angle)
        far = JUNCTION_HALF + ARM
        road = sub(
            root, "road", name=f"arm {arm_id}", length=ARM, id=arm_id, junction="-1", rule="RHT"
        )
        sub(sub(road, "link"), "successor", elementType="junction", elementId=junction_id)
        road_type = sub(road, "type", s=0.0, type="town")
        sub(road_type, "speed", max="50", unit="km/h")
        # Each arm runs towards the junction: lane -1 drives in, lane 1 drives out.
        plan_view(
            road, chain(far * math.cos(a), far * math.sin(a), a + math.pi, [Piece("line", ARM)])
        )
        two_way_lanes(road, "sidewalk", 2.0)
        signals = sub(road, "signals")
        sub(
            signals,
            "signal",
            s=ARM - 1.0,
            t=-(LANE + 2.5),
            id=f"tl{arm_id}",
            name=f"traffic light arm {arm_id}",
            dynamic="yes",
            orientation="+",
            zOffset=0.0,
            country="DE",
            type="1000001",
            subtype="-1",
            height=3.0,
            width=0.4,
        )
        signal = signals[-1]
        sub(signal, "validity", fromLane=-1, toLane=-1)

    next_id = 101
    names = {0: "straight", 1: "left", -1: "right"}
    for arm_id, angle in arms.items():
        a = math.radians(angle)
        start = (JUNCTION_HALF * math.cos(a), JUNCTION_HALF * math.sin(a), a + math.pi)
        for step, turn in ((2, 0), (1, -1), (3, 1)):
            target = str((int(arm_id) - 1 + step) % 4 + 1)
            if turn == 0:
                pieces = [Piece("line", 2.0 * JUNCTION_HALF)]
            else:
                pieces = turn_pieces(float(turn))
            records = chain(*start, pieces)
            road_id = str(next_id)
            next_id += 1
            length = sum(p.length for p in pieces)
            road = sub(
                root,
                "road",
                name=f"{names[turn]} {arm_id} to {target}",
                length=length,
                id=road_id,
                junction=junction_id,
                rule="RHT",
            )
            link = sub(road, "link")
            sub(link, "predecessor", elementType="road", elementId=arm_id, contactPoint="end")
            sub(link, "successor", elementType="road", elementId=target, contactPoint="end")
            plan_view(road, records)
            section = sub(sub(road, "lanes"), "laneSection", s=0.0)
            sub(sub(section, "center"), "lane", id=0, type="none", level="false")
            lane(sub(section, "right"), -1, "driving", LANE, predecessor=-1, successor=1)
            connections.append((arm_id, road_id))
    # OpenDRIVE orders a file as header, roads, controllers, junctions (the 1.8 schema)
    for controller_id, members in (("ns", ("2", "4")), ("ew", ("1", "3"))):
        controller = sub(
            root,
            "controller",
            id=controller_id,
            name=f"{controller_id} lights",
            sequence=1 if controller_id == "ns" else 2,
        )
        for arm_id in members:
            sub(controller, "control", signalId=f"tl{arm_id}", type="0")
    junction = sub(root, "junction", id=junction_id, name="four-way crossing", type="default")
    for number, (incoming, connecting) in enumerate(connections):
        connection = sub(
            junction,
            "connection",
            id=str(number),
            incomingRoad=incoming,
            connectingRoad=connecting,
            contactPoint="start",
        )
        sub(connection, "laneLink", from_=-1, to=-1)
    return root


MAPS = {"rural_curves.xodr": rural_curves, "four_way_junction.xodr": four_way_junction}


def write_maps(folder: Path) -> list[Path]:
    """Write every bundled map into ``folder``; returns the paths."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name, make in MAPS.items():
        root = make()
        ET.indent(root, space="  ")
        path = folder / name
        text = ET.tostring(root, encoding="unicode")
        path.write_text('<?xml version="1.0" encoding="utf-8"?>\n' + text + "\n", encoding="utf-8")
        written.append(path)
    return written


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent
    for path in write_maps(out):
        print(path)
