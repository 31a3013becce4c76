"""A small OpenSCENARIO reader that replays exported trajectories, as a player does.

It reads only the XML: each entity's bounding-box centre (relative to its reference
point), its ``TeleportAction`` in ``Init`` and the ``Polyline`` of its
``FollowTrajectoryAction`` (``Timing`` absolute), and gives the bounding-box centre and
heading at any time by linear interpolation between the vertices (headings as written,
so unwrapped headings never turn the long way round).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class Replayed:
    name: str
    centre_x: float  # bounding-box centre ahead of the reference point
    start: tuple[float, float, float]  # Init teleport: x, y, h of the reference point
    times: np.ndarray
    x: np.ndarray
    y: np.ndarray
    h: np.ndarray

    def pose(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Bounding-box centre x, y and heading at times ``t``."""
        if len(self.times) == 0:
            n = len(t)
            x, y, h = (np.full(n, v) for v in self.start)
        else:
            x = np.interp(t, self.times, self.x)
            y = np.interp(t, self.times, self.y)
            h = np.interp(t, self.times, self.h)
        return x + self.centre_x * np.cos(h), y + self.centre_x * np.sin(h), h


def read_replay(path: Path) -> tuple[dict[str, Replayed], float]:
    """Every entity of the export at ``path`` and the storyboard's stop time."""
    root = ET.parse(path).getroot()
    found: dict[str, Replayed] = {}
    for obj in root.iter("ScenarioObject"):
        centre = obj.find(".//BoundingBox/Center")
        assert centre is not None
        empty = np.zeros(0)
        found[obj.get("name", "")] = Replayed(
            obj.get("name", ""), float(centre.get("x", "0")), (0.0, 0.0, 0.0), empty, empty,
            empty, empty,
        )  # fmt: skip
    for private in root.iter("Private"):
        world = private.find(".//TeleportAction/Position/WorldPosition")
        if world is not None:
            entry = found[private.get("entityRef", "")]
            entry.start = tuple(float(world.get(k, "0")) for k in ("x", "y", "h"))  # type: ignore[assignment]
    for group in root.iter("ManeuverGroup"):
        ref = group.find("Actors/EntityRef")
        follow = group.find(".//FollowTrajectoryAction")
        if ref is None or follow is None:
            continue
        timing = follow.find("TimeReference/Timing")
        assert timing is not None and timing.get("domainAbsoluteRelative") == "absolute"
        assert float(timing.get("scale", "0")) == 1.0 and float(timing.get("offset", "1")) == 0.0
        vertices = follow.findall(".//Polyline/Vertex")
        rows = []
        for v in vertices:
            w = v.find("Position/WorldPosition")
            assert w is not None
            rows.append((float(v.get("time", "nan")), *(float(w.get(k, "nan")) for k in "xyh")))
        table = np.array(rows)
        entry = found[ref.get("entityRef", "")]
        entry.times, entry.x, entry.y, entry.h = table.T
    stop = root.find("Storyboard/StopTrigger//SimulationTimeCondition")
    assert stop is not None
    return found, float(stop.get("value", "nan"))


def heading_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| wrapped into [0, π]."""
    d = (np.asarray(a) - np.asarray(b) + math.pi) % (2.0 * math.pi) - math.pi
    return np.abs(d)
