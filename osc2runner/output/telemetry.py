"""Telemetry: what every actor did at every control tick, the event log, and the run's metadata.

Per actor per tick (SI units, world frame): ``tick, time, x, y, yaw, speed,
accel, jerk, throttle, brake, steer, lane, friction``. ``accel`` is the
change of speed over the last tick (50 ms by default); ``jerk`` is the jerk
averaged over the last second, i.e. ``(accel(t) - accel(t - 1 s)) / 1 s``
(over the time since the start during the first second). ``lane`` is the
number of the driving lane the actor is in, counted from the right in its
direction of travel (1 = rightmost; NaN outside driving lanes);
``throttle``/``brake``/``steer`` (NaN for actors without them) are the applied
inputs; ``lateral_error`` is the lateral controller's cross-track error of the
front axle from its path (m, positive: left of the path; NaN without one).
``road`` (the road id, empty off every road), ``lane_id`` (the OpenDRIVE id of
the lane it is in, 0 off the roads), ``s`` and ``t`` (road coordinates on that
road, NaN off the roads) say where the actor is on the map; ``distance`` is how
far it has travelled along its path since its start (the witness's ``s`` counts
along the actor's carriageway in its direction of travel, so its start ``s`` plus
``distance`` is its position along its route in the witness's measure, while the
road's ``s`` follows the road's reference line, decreasing in a lane that drives
against it, and starts again on each road); ``articulation`` is a hitched
trailer's articulation angle (its tow vehicle's heading less its own, rad; NaN for
other actors and unhitched trailers).

Files (``write_data``, then ``write_metadata``; ``write`` does both), each
written whole or not at all (:mod:`osc2runner.output.files`):

* ``telemetry.csv``: one row per actor and tick, columns as above after
  ``actor``; floats written with ``repr`` (exact, so identical runs give
  identical bytes), times at the precision of the control period (``13.6``, not
  ``13.600000000000001``: :func:`tick_time`);
* ``events.csv``: the event log (``tick, time, kind, name, actors, detail``);
* ``run.json``: metadata (versions, seed, steps, parameter values, actors,
  outcome) and the event log. The runner writes it last, after the plots.
"""

from __future__ import annotations

import csv
import json
import math
from collections.abc import Iterable, Mapping
from decimal import Decimal
from pathlib import Path
from typing import Any

import numpy as np

from osc2runner.execution.context import LogRecord
from osc2runner.execution.controls import Controller
from osc2runner.output.files import atomic_open, write_atomically
from osc2runner.sim import ActorState

__all__ = ["CHANNELS", "Recorder", "tick_time", "write_data", "write_metadata"]

CHANNELS = (
    "tick",
    "time",
    "x",
    "y",
    "yaw",
    "speed",
    "accel",
    "jerk",
    "throttle",
    "brake",
    "steer",
    "lane",
    "friction",
    "lateral_error",
    "road",
    "lane_id",
    "s",
    "t",
    "distance",
    "articulation",
)
TEXT_CHANNELS = frozenset({"road"})
JERK_WINDOW = 1.0  # s


def tick_time(time: float, dt: float) -> float:
    """``time``, a whole number of control periods ``dt``, at the period's precision: the
    decimals of ``dt`` (``272 * 0.05`` is ``13.6``, not ``13.600000000000001``)."""
    exponent = Decimal(repr(dt)).normalize().as_tuple().exponent
    return round(time, max(0, -int(exponent))) if isinstance(exponent, int) else time


class Recorder:
    """Collects one row per actor per tick (see the module docstring).

    Parameters:
        names: the actors to record, in order.
        dt: control period in seconds (for the jerk window).

    ``clock`` holds each recorded tick and its time; ``rows[actor]`` the actor's
    channels after them, one tuple per tick. An actor whose state is the very same
    object as at the tick before (a walker standing still keeps its state), with
    the same path error and a settled jerk, gets the same row again: nothing is
    computed for it.
    """

    def __init__(self, names: Iterable[str], dt: float, jerk_window: float = JERK_WINDOW) -> None:
        self.names = list(names)
        self.dt = dt
        self.window = max(1, round(jerk_window / dt))
        self.clock: list[tuple[int, float]] = []
        self.rows: dict[str, list[tuple[float | str, ...]]] = {n: [] for n in self.names}
        self._accel: dict[str, list[float]] = {n: [] for n in self.names}
        self._last: dict[str, tuple[object, float, int]] = {}  # state, error, ticks unchanged
        self._path: dict[str, tuple[float, float, float]] = {}  # x, y, distance travelled

    def record(
        self,
        states: Mapping[str, ActorState],
        tick: int,
        time: float,
        controllers: Mapping[str, Controller] | None = None,
    ) -> None:
        """Add this tick's row of every actor (``controllers`` give the path errors)."""
        window = self.window
        controllers = controllers or {}
        self.clock.append((tick, tick_time(time, self.dt)))
        last = self._last
        for name in self.names:
            s = states[name]
            ctrl = controllers.get(name)
            lateral = ctrl.lateral if ctrl is not None else None
            error = lateral.error if lateral is not None and lateral.path is not None else math.nan
            tracker = ctrl.path if ctrl is not None else None  # a world path (follow_path)
            if tracker is not None and hasattr(tracker, "error"):
                error = tracker.error
            rows = self.rows[name]
            before = last.get(name)
            if before is not None and before[0] is s and before[1] is error:
                if before[2] > window:  # the jerk window holds this state only: the same row
                    rows.append(rows[-1])
                    continue
                last[name] = (s, error, before[2] + 1)
            else:
                last[name] = (s, error, 0)
            x0, y0, travelled = self._path.get(name, (s.x, s.y, 0.0))
            travelled += math.hypot(s.x - x0, s.y - y0)
            self._path[name] = (s.x, s.y, travelled)
            history = self._accel[name]
            history.append(s.accel)
            n = len(history)
            if n > 1:
                back = min(window, n - 1)
                jerk = (s.accel - history[n - 1 - back]) / (back * self.dt)
            else:
                jerk = 0.0
            if n > window + 1:
                del history[0]
            lane = float(s.lane) if s.lane is not None else math.nan
            rows.append(
                (
                    s.x,
                    s.y,
                    s.yaw,
                    s.speed,
                    s.accel,
                    jerk,
                    s.throttle,
                    s.brake,
                    s.steer,
                    lane,
                    s.friction,
                    error,
                    s.road if s.road is not None else "",
                    s.lane_id,
                    s.s,
                    s.t,
                    travelled,
                    s.articulation,
                )
            )

    @property
    def ticks(self) -> int:
        return len(self.clock)

    def arrays(self) -> dict[str, dict[str, np.ndarray]]:
        """Per actor, per channel: a numpy array over the recorded ticks."""
        result: dict[str, dict[str, np.ndarray]] = {}
        ticks = np.array([c[0] for c in self.clock], dtype=np.int64)
        times = np.array([c[1] for c in self.clock], dtype=float)
        channels = CHANNELS[2:]  # after tick and time
        road = channels.index("road")
        numeric = [i for i, c in enumerate(channels) if c not in TEXT_CHANNELS]
        for name, rows in self.rows.items():
            table = np.array([[row[i] for i in numeric] for row in rows], dtype=float).reshape(
                -1, len(numeric)
            )
            columns = {channels[i]: table[:, k].copy() for k, i in enumerate(numeric)}
            columns["road"] = np.array([str(row[road]) for row in rows], dtype=str)
            columns["tick"], columns["time"] = ticks.copy(), times.copy()
            columns["lane_id"] = columns["lane_id"].astype(np.int64)
            result[name] = {c: columns[c] for c in CHANNELS}
        return result


def _number(value: float | str) -> str:
    kind = type(value)
    if kind is float:  # nearly every value: repr gives `nan` and `inf` as the cases below
        return repr(value)
    if kind is str:
        return value  # type: ignore[return-value]  # narrowed by the test of its type
    if isinstance(value, str):
        return value
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if math.isnan(value):
        return "nan"
    return repr(float(value))


def write_telemetry(path: Path, recorder: Recorder) -> None:
    with atomic_open(path, "w", newline="", encoding="utf-8") as f:
        f.write("actor," + ",".join(CHANNELS) + "\n")
        clock = [f"{tick},{_number(time)}," for tick, time in recorder.clock]
        for name, rows in recorder.rows.items():
            lines: list[str] = []
            row_before: object = None
            text = ""
            for when, row in zip(clock, rows, strict=True):
                if row is not row_before:  # a standing actor repeats one row object
                    text, row_before = ",".join(map(_number, row)), row
                lines.append(f"{name},{when}{text}\n")
            f.write("".join(lines))


def write_events(path: Path, records: Iterable[LogRecord], dt: float) -> None:
    with atomic_open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(["tick", "time", "kind", "name", "actors", "detail"])
        for r in records:
            when = repr(tick_time(r.time, dt))
            writer.writerow([r.tick, when, r.kind, r.name, " ".join(r.actors), r.detail])


def event_dicts(records: Iterable[LogRecord], dt: float) -> list[dict[str, Any]]:
    return [
        {
            "tick": r.tick,
            "time": tick_time(r.time, dt),
            "kind": r.kind,
            "name": r.name,
            "actors": list(r.actors),
            "detail": r.detail,
        }
        for r in records
    ]


def write_data(out: Path, recorder: Recorder, records: list[LogRecord]) -> list[Path]:
    """Write ``telemetry.csv`` and ``events.csv`` into the folder ``out``; returns the paths."""
    telemetry = out / "telemetry.csv"
    events = out / "events.csv"
    write_telemetry(telemetry, recorder)
    write_events(events, records, recorder.dt)
    return [telemetry, events]


def write_metadata(out: Path, metadata: dict[str, Any], records: list[LogRecord]) -> Path:
    """Write ``run.json`` (``metadata`` and the event log) into the folder ``out``."""
    document = dict(metadata)
    document["events"] = event_dicts(records, metadata["dt_control"])
    text = json.dumps(document, indent=2, default=_json_default) + "\n"
    return write_atomically(out / "run.json", text)


def _json_default(value: object) -> object:
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return str(value)
