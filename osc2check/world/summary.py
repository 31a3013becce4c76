"""A road network in a few lines: counts and lengths for the editor's hover and listings."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from osc2check.world.network import RoadNetwork

__all__ = ["NetworkSummary", "summarize"]


@dataclass(frozen=True, slots=True)
class NetworkSummary:
    """What a person wants to know about a map at a glance.

    ``lanes_by_type`` counts lanes per lane section (a lane that runs through
    three sections counts three times); lengths are reference-line lengths.
    """

    name: str
    source: str | None
    roads: int
    junction_roads: int
    junctions: int
    lanes_by_type: dict[str, int]
    total_length: float
    driving_lane_length: float
    signals: int
    traffic_lights: int
    bounds: tuple[float, float, float, float]
    revision: tuple[int, int] | None
    warnings: int
    description: str

    def text(self) -> str:
        """A few Markdown lines for an editor hover."""
        kind = (
            f"OpenDRIVE {self.revision[0]}.{self.revision[1]}"
            if self.revision
            else "built-in map"
            if self.source is None
            else "map"
        )
        lines = [f"**{self.name}** ({kind})"]
        if self.description:
            lines.append(self.description)
        lines.append(
            f"{self.roads} road(s), {self.total_length:.0f} m; "
            f"{self.junctions} junction(s) with {self.junction_roads} connecting road(s)"
        )
        lanes = ", ".join(f"{count} {kind}" for kind, count in sorted(self.lanes_by_type.items()))
        lines.append(f"lanes: {lanes}; driving lanes {self.driving_lane_length:.0f} m")
        if self.signals:
            lines.append(f"{self.signals} signal(s), {self.traffic_lights} traffic light(s)")
        x0, x1, y0, y1 = self.bounds
        lines.append(f"extent {x1 - x0:.0f} m x {y1 - y0:.0f} m")
        if self.warnings:
            lines.append(f"{self.warnings} warning(s) while reading")
        return "  \n".join(lines)


def summarize(network: RoadNetwork) -> NetworkSummary:
    """The :class:`NetworkSummary` of ``network``."""
    lanes = Counter(lane.type for lane in network.lanes())
    driving = sum(network.section(lane.ref).length for lane in network.driving_lanes())
    return NetworkSummary(
        name=network.name,
        source=network.source,
        roads=len(network.roads),
        junction_roads=sum(1 for r in network.roads.values() if r.junction is not None),
        junctions=len(network.junctions),
        lanes_by_type=dict(lanes),
        total_length=sum(r.length for r in network.roads.values()),
        driving_lane_length=driving,
        signals=len(network.signals),
        traffic_lights=sum(1 for s in network.signals if s.dynamic),
        bounds=network.bounds(),
        revision=network.revision,
        warnings=len(network.warnings),
        description=network.description,
    )
