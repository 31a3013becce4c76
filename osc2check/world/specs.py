"""What a road network is made of, as written: the input of :mod:`osc2check.world.layout`.

An OpenDRIVE file is read into these records (:mod:`.opendrive.reader`) and the
built-in straight maps are written as them in code (:mod:`.builtin`); both then
go through the same layout step, so the two kinds of map cannot drift apart.
The records keep the file's values and source lines and nothing derived: no
samples, no lane directions, no resolved links.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from osc2check.world.geometry import Cubic, Geometry
from osc2check.world.network import (
    Controller,
    Crossing,
    Junction,
    Numbering,
    RoadLink,
    Signal,
    SignalReference,
)

__all__ = ["LaneSpec", "NetworkSpec", "RoadSpec", "SectionSpec"]


@dataclass(frozen=True, slots=True)
class LaneSpec:
    """A ``<lane>`` (not the centre lane): id, type, width or border records, links, speed."""

    id: int
    type: str
    widths: tuple[Cubic, ...] = ()
    borders: tuple[Cubic, ...] = ()
    direction: str | None = None
    predecessors: tuple[int, ...] = ()
    successors: tuple[int, ...] = ()
    speed_limit: float | None = None
    line: int | None = None
    column: int | None = None


@dataclass(frozen=True, slots=True)
class SectionSpec:
    """A ``<laneSection>``: its start ``s`` and its side lanes in any order."""

    s: float
    lanes: tuple[LaneSpec, ...]
    single_side: bool = False
    line: int | None = None
    column: int | None = None


@dataclass(frozen=True, slots=True)
class RoadSpec:
    """A ``<road>`` as written."""

    id: str
    name: str
    length: float
    junction: str | None
    geometries: tuple[Geometry, ...]
    sections: tuple[SectionSpec, ...]
    rule: Literal["RHT", "LHT"] = "RHT"
    predecessor: RoadLink | None = None
    successor: RoadLink | None = None
    lane_offsets: tuple[Cubic, ...] = ()
    elevation: tuple[Cubic, ...] = ()
    speed_limit: float | None = None
    signals: tuple[Signal, ...] = ()
    signal_references: tuple[SignalReference, ...] = ()
    crossings: tuple[Crossing, ...] = ()
    line: int | None = None
    column: int | None = None


@dataclass(frozen=True, slots=True)
class NetworkSpec:
    """A whole map as written, plus how its scenarios number lanes."""

    name: str
    roads: tuple[RoadSpec, ...]
    junctions: tuple[Junction, ...] = ()
    controllers: tuple[Controller, ...] = ()
    revision: tuple[int, int] | None = None
    source: str | None = None
    numbering: Numbering = "from_right"
    speed_limit: float | None = None
    description: str = ""
