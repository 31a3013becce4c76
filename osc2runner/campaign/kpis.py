"""Key performance indicators of one run, from its telemetry and event log.

Computed for the run's **subject**: the system under test's actor, else the
field named ``sut`` or ``ego``, else the first vehicle. Every figure is a plain
number (or None when it does not apply) with its unit in its name:

==========================  ===================================================
``collision``               whether any collision was logged
``collision_with``          the actor the subject collided with first (None)
``collision_time_s``        when
``impact_speed_kph``        the subject's speed at its first collision
``relative_impact_speed_kph``  the closing speed at that collision (along the
                            subject's heading): what a crash test grades
``speed_reduction_kph``     the subject's start speed less its impact speed
                            (a run without a collision: its start speed)
``min_ttc_s``               smallest time to collision with an actor in the
                            subject's path that it closes in on (gap / closing
                            speed; None when it never closes in on one)
``min_gap_m``               smallest bumper-to-bumper gap to an actor whose
                            width overlaps the subject's (0 at contact)
``max_decel_mps2``          largest deceleration (50 ms speed change)
``max_jerk_mps3``           largest absolute jerk (1 s window, as telemetry)
``time_to_stop_s``          from the first brake onset (brake pedal above 5 %
                            while faster than 1 m/s) to standstill (< 0.1 m/s);
                            None when it does not stop after braking
``lane_departures``         how many times the subject's centre crossed into
                            another lane or off the road
==========================  ===================================================

Actors are taken as boxes aligned with their heading, and each other actor's
velocity as its speed along its heading (telemetry has no lateral speed of
others); the gaps use the boxes' extents projected on the subject's axes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from osc2runner.output.gaps import boxes
from osc2runner.output.stops import BRAKE_ONSET, MOVING, STANDSTILL

__all__ = ["KPI_UNITS", "closing_speed", "kpi_text", "run_kpis"]

#: every KPI and its unit (for tables and reports), in the order shown
KPI_UNITS: dict[str, str] = {
    "collision": "",
    "collision_with": "",
    "collision_time_s": "s",
    "impact_speed_kph": "kph",
    "relative_impact_speed_kph": "kph",
    "speed_reduction_kph": "kph",
    "min_ttc_s": "s",
    "min_gap_m": "m",
    "max_decel_mps2": "m/s²",
    "max_jerk_mps3": "m/s³",
    "time_to_stop_s": "s",
    "lane_departures": "",
}

KPH = 3.6
#: the KPIs a one-line account of a run gives, in this order
TOLD = (
    "relative_impact_speed_kph",
    "impact_speed_kph",
    "speed_reduction_kph",
    "min_ttc_s",
    "min_gap_m",
    "max_decel_mps2",
)


def kpi_text(kpis: Mapping[str, Any]) -> str:
    """The KPIs of a run that it has, as ``name value unit`` separated by commas."""
    parts = []
    for name in TOLD:
        value = kpis.get(name)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            unit = KPI_UNITS[name]
            parts.append(f"{name} {value:g}{' ' + unit if unit else ''}")
    return ", ".join(parts)


def _num(value: float | None, digits: int = 4) -> float | None:
    if value is None or not math.isfinite(value):
        return None
    return round(float(value), digits)


def run_kpis(
    telemetry: Mapping[str, Mapping[str, np.ndarray]],
    sizes: Mapping[str, tuple[float, float]],
    collisions: Sequence[tuple[int, tuple[str, ...]]],
    subject: str | None,
    start_speed: float | None = None,
) -> dict[str, Any]:
    """The KPIs (see the module docstring) of one run.

    Parameters:
        telemetry: actor -> channel -> array (``RunResult.telemetry``).
        sizes: actor -> (length, width) in m, for actors with a body.
        collisions: ``(tick, actors)`` of each collision logged, in order.
        subject: the actor the KPIs are about (None: only ``collision``).
        start_speed: the subject's start speed (m/s), for the speed reduction.
    """
    kpis: dict[str, Any] = dict.fromkeys(KPI_UNITS)
    kpis["collision"] = bool(collisions)
    kpis["lane_departures"] = 0
    if subject is None or subject not in telemetry:
        return kpis
    me = telemetry[subject]
    ticks = me["tick"]
    speed = me["speed"]
    if start_speed is None:
        start_speed = float(speed[0]) if len(speed) else 0.0
    mine = [(t, a) for t, a in collisions if subject in a]
    if mine:
        tick, actors = mine[0]
        other = next((a for a in actors if a != subject), None)
        kpis["collision_with"] = other
        row = int(np.searchsorted(ticks, tick)) if len(ticks) else 0
        row = min(row, len(ticks) - 1)
        kpis["collision_time_s"] = _num(float(me["time"][row]), 3)
        v = float(speed[row])
        kpis["impact_speed_kph"] = _num(v * KPH, 2)
        kpis["speed_reduction_kph"] = _num((start_speed - v) * KPH, 2)
        if other is not None and other in telemetry:
            closing = closing_speed(me, telemetry[other], row)
            kpis["relative_impact_speed_kph"] = _num(closing * KPH, 2)
    else:
        kpis["speed_reduction_kph"] = _num(start_speed * KPH, 2)  # avoided: all of it
    accel = me["accel"]
    if len(accel):
        kpis["max_decel_mps2"] = _num(max(0.0, float(-accel.min())), 3)
        kpis["max_jerk_mps3"] = _num(float(np.abs(me["jerk"]).max()), 3)
    kpis["time_to_stop_s"] = _time_to_stop(me)
    kpis["lane_departures"] = _lane_departures(me["lane"])
    ttc, gap = _ttc_and_gap(telemetry, sizes, subject)
    kpis["min_ttc_s"] = _num(ttc, 3)
    kpis["min_gap_m"] = _num(gap, 3)
    return kpis


def closing_speed(me: Mapping[str, np.ndarray], other: Mapping[str, np.ndarray], row: int) -> float:
    """Closing speed of ``me`` on ``other`` along ``me``'s heading at ``row``."""
    row = min(row, len(other["speed"]) - 1)
    yaw = float(me["yaw"][row])
    c, s = math.cos(yaw), math.sin(yaw)
    mine = float(me["speed"][row])
    vx = float(other["speed"][row]) * math.cos(float(other["yaw"][row]))
    vy = float(other["speed"][row]) * math.sin(float(other["yaw"][row]))
    return mine - (vx * c + vy * s)


def _time_to_stop(me: Mapping[str, np.ndarray]) -> float | None:
    brake, speed, time = me["brake"], me["speed"], me["time"]
    if not len(brake) or np.isnan(brake).all():
        return None
    braking = (np.nan_to_num(brake) > BRAKE_ONSET) & (speed > MOVING)
    onsets = np.flatnonzero(braking)
    if not len(onsets):
        return None
    start = int(onsets[0])
    stopped = np.flatnonzero(speed[start:] < STANDSTILL)
    if not len(stopped):
        return None
    return _num(float(time[start + int(stopped[0])] - time[start]), 3)


def _lane_departures(lane: np.ndarray) -> int:
    """Changes of the lane value (a NaN, off the road, counts as a lane of its own)."""
    if len(lane) < 2:
        return 0
    marked = np.where(np.isnan(lane), -1.0, lane)
    return int(np.count_nonzero(np.diff(marked) != 0))


def _ttc_and_gap(
    telemetry: Mapping[str, Mapping[str, np.ndarray]],
    sizes: Mapping[str, tuple[float, float]],
    subject: str,
) -> tuple[float | None, float | None]:
    me = telemetry[subject]
    mine = sizes.get(subject, (0.0, 0.0))
    v = me["speed"]
    best_ttc, best_gap = math.inf, math.inf
    for name, other in telemetry.items():
        if name == subject or name not in sizes:
            continue
        seen = boxes(me, other, mine, sizes[name])
        n = len(seen.gap)
        if n == 0:
            continue
        overlapping = seen.lateral_gap < 0.0
        if overlapping.any():
            best_gap = min(best_gap, float(np.maximum(seen.gap[overlapping], 0.0).min()))
        closing = v[:n] - other["speed"][:n] * np.cos(seen.dyaw)  # along the subject's heading
        ahead = overlapping & (seen.rel_x > 0.0) & (closing > 1e-6)
        if ahead.any():
            ttc = np.maximum(seen.gap[ahead], 0.0) / closing[ahead]
            best_ttc = min(best_ttc, float(ttc.min()))
    return (
        best_ttc if math.isfinite(best_ttc) else None,
        best_gap if math.isfinite(best_gap) else None,
    )
