"""``lights.csv``: what every traffic light shows at every control tick.

One row per light per tick, as ``telemetry.csv`` has one per actor per tick
(that file keeps its columns: lights are not actors with a pose and speed):

``light, tick, time, semantic, bulbs``

* ``semantic``: the semantic state the bulbs express (``stop``, ``go``, ...,
  ``off``; :func:`osc2runner.instance.lights.semantic_of`);
* ``bulbs``: every bulb in the light's order as ``colour/icon/state``,
  separated by spaces (``red/circle/is_on yellow/circle/is_off
  green/circle/is_off``).

The row at tick ``k`` is what the light shows from the time of tick ``k`` on: a
change the event log records at tick ``k`` (an action of that tick switched it)
is in that row. The rows are expanded once from each light's history of changes
when the run ends (the result's ``lights``, which the file is written from), so
a light that does not change costs nothing while the run ticks. The file is
written (whole or not at all) when the scenario has traffic lights; the lights'
places are in ``run.json``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np

from osc2runner.instance.lights import LightState, TrafficLight
from osc2runner.output.files import atomic_open
from osc2runner.output.telemetry import tick_time

__all__ = ["LIGHT_COLUMNS", "light_arrays", "light_rows", "write_lights"]

LIGHT_COLUMNS = ("tick", "time", "semantic", "bulbs")


def _bulbs(state: LightState) -> str:
    return " ".join("/".join(bulb) for bulb in state.bulbs)


def light_rows(light: TrafficLight, ticks: int, dt: float) -> Iterator[tuple[int, float, str, str]]:
    """``(tick, time, semantic, bulbs)`` of ``light`` for ticks ``0 .. ticks - 1``."""
    history = light.history
    k = 0
    for tick in range(ticks):
        while k + 1 < len(history) and history[k + 1].tick <= tick:
            k += 1
        state = history[k]
        yield tick, tick_time(tick * dt, dt), state.semantic, _bulbs(state)


def light_arrays(
    lights: Iterable[TrafficLight], ticks: int, dt: float
) -> dict[str, dict[str, np.ndarray]]:
    """Per light, per column of ``lights.csv``: a numpy array over the ticks."""
    result: dict[str, dict[str, np.ndarray]] = {}
    for light in lights:
        rows = list(light_rows(light, ticks, dt))
        result[light.name] = {
            "tick": np.array([r[0] for r in rows], dtype=np.int64),
            "time": np.array([r[1] for r in rows], dtype=float),
            "semantic": np.array([r[2] for r in rows], dtype=str),
            "bulbs": np.array([r[3] for r in rows], dtype=str),
        }
    return result


def write_lights(path: Path, lights: dict[str, dict[str, np.ndarray]]) -> Path:
    """Write ``lights.csv`` (see the module docstring) from the lights' columns
    (:func:`light_arrays`); returns the path."""
    with atomic_open(path, "w", newline="", encoding="utf-8") as f:
        f.write("light," + ",".join(LIGHT_COLUMNS) + "\n")
        for name, columns in lights.items():
            rows = zip(*(columns[c].tolist() for c in LIGHT_COLUMNS), strict=True)
            for tick, time, semantic, bulbs in rows:
                f.write(f"{name},{tick},{time!r},{semantic},{bulbs}\n")
    return path
