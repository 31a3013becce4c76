"""Who a run is about, and the gaps between actors' boxes, read from telemetry.

One definition for the KPIs (``campaign/kpis.py``), the plots (``output/plots.py``)
and the run's summary: actors are boxes aligned with their heading; seen from
``me``, another actor's box is projected on ``me``'s axes, and the gaps are
bumper to bumper (longitudinal) and side to side (lateral), as the scenario's
``position(distance: ...)``, the witness and the SUT's ``gap`` count them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Boxes", "boxes", "subject_actor"]


def subject_actor(actors: Mapping[str, Mapping[str, Any]], sut: str | None) -> str | None:
    """The run's subject among ``actors`` (run.json's ``actors``: name -> entry with a
    ``kind``): ``sut``, else ``sut``/``ego`` fields, else the first vehicle."""
    if sut is not None:
        return sut
    vehicles = [n for n, a in actors.items() if a.get("kind") == "vehicle"]
    for name in ("sut", "ego"):
        if name in vehicles:
            return name
    return vehicles[0] if vehicles else None


@dataclass(frozen=True)
class Boxes:
    """Another actor seen from ``me``, per tick (arrays of the ticks both have).

    ``rel_x`` (forward) and ``rel_y`` (left): its centre in ``me``'s axes; ``gap``:
    bumper to bumper along ``me``'s heading (negative while the boxes overlap
    lengthwise); ``lateral_gap``: side to side (negative: the widths overlap, it is
    in ``me``'s path); ``dyaw``: its heading less ``me``'s.
    """

    rel_x: np.ndarray
    rel_y: np.ndarray
    gap: np.ndarray
    lateral_gap: np.ndarray
    dyaw: np.ndarray

    @property
    def signed_gap(self) -> np.ndarray:
        """The bumper-to-bumper gap, positive ahead of ``me``, negative behind, 0 while
        the boxes overlap lengthwise (alongside, or in contact)."""
        gap: np.ndarray = np.sign(self.rel_x) * np.maximum(self.gap, 0.0)
        return gap


def boxes(
    me: Mapping[str, np.ndarray],
    other: Mapping[str, np.ndarray],
    my_size: tuple[float, float],
    other_size: tuple[float, float],
) -> Boxes:
    """``other`` seen from ``me`` (telemetry channels ``x``, ``y``, ``yaw``); sizes are
    ``(length, width)`` in m."""
    n = min(len(me["x"]), len(other["x"]))
    x, y, yaw = me["x"][:n], me["y"][:n], me["yaw"][:n]
    c, s = np.cos(yaw), np.sin(yaw)
    dx, dy = other["x"][:n] - x, other["y"][:n] - y
    rel_x = dx * c + dy * s
    rel_y = -dx * s + dy * c
    dyaw = other["yaw"][:n] - yaw
    rc, rs = np.abs(np.cos(dyaw)), np.abs(np.sin(dyaw))
    length, width = other_size
    half_long = 0.5 * (length * rc + width * rs)
    half_lat = 0.5 * (length * rs + width * rc)
    return Boxes(
        rel_x,
        rel_y,
        np.abs(rel_x) - 0.5 * my_size[0] - half_long,
        np.abs(rel_y) - 0.5 * my_size[1] - half_lat,
        dyaw,
    )
