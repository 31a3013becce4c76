"""PNG plots of a run, of the kinds the design paper shows.

* ``speed_throttle.png``: speed, and throttle and brake, over time;
* ``accel_jerk.png``: acceleration and the 1 s-filtered jerk over time;
* ``braking.png``: speed against the distance travelled since each brake
  onset (when the run has hard or comfortable stops);
* ``gap_steering.png``: the longitudinal gap from the first vehicle to each
  other actor (projected on its heading), and the steering inputs;
* ``world.png``: a bird's-eye view: the map's lanes (driving lanes grey, junction
  roads darker, sidewalks and other lane types paler) under every actor's path
  (its start a circle, its end a square) and the traffic lights in their last
  state; the view is the paths with a margin (or the whole map, when smaller);
  below, each light's semantic state over time.

Emitted events are marked on the time axes. Figures are drawn with
matplotlib's Agg canvas directly (no pyplot state, no display needed), each
written whole or not at all (:func:`osc2runner.output.files.atomic_open`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from osc2check.world.network import RoadNetwork
from osc2runner.output.files import atomic_open
from osc2runner.output.stops import BRAKE_ONSET, MOVING, STANDSTILL

__all__ = ["brake_onsets", "plot_run"]

KPH = 3.6


def _figure(rows: int) -> tuple[Figure, list[Any]]:
    fig = Figure(figsize=(10, 3.2 * rows), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    axes = [fig.add_subplot(rows, 1, i + 1) for i in range(rows)]
    return fig, axes


def _mark_events(ax: Any, result: Any) -> None:
    for e in result.events:
        if e.kind == "emit":
            ax.axvline(e.time, color="0.6", lw=0.8, ls="--")
            ax.annotate(
                e.name,
                (e.time, 1.0),
                xycoords=("data", "axes fraction"),
                rotation=90,
                va="top",
                ha="right",
                fontsize=7,
                color="0.4",
            )


def _moving(result: Any) -> dict[str, dict[str, np.ndarray]]:
    return {
        n: ch
        for n, ch in result.telemetry.items()
        if not np.all(np.isnan(ch["throttle"])) or np.any(ch["speed"] != 0.0)
    }


def brake_onsets(ch: dict[str, np.ndarray], quiet: float = 1.0) -> list[tuple[int, int]]:
    """``(start, end)`` tick indices of each stop: brake applied after ``quiet`` s without,
    while moving, until standstill (the thresholds of the ``time_to_stop_s`` KPI)."""
    brake, speed, time = ch["brake"], ch["speed"], ch["time"]
    segments: list[tuple[int, int]] = []
    last_free = 0.0
    i, n = 0, len(time)
    while i < n:
        b = brake[i]
        if not (b > BRAKE_ONSET) or math.isnan(b):
            last_free = time[i]
            i += 1
            continue
        if (
            time[i] - last_free > 0.2
            or not speed[i] > MOVING
            or (segments and time[i] - time[segments[-1][1]] < quiet)
        ):
            i += 1
            continue
        start = max(i - 1, 0)
        j = i
        while j < n - 1 and not speed[j] < STANDSTILL:
            j += 1
        if speed[j] < STANDSTILL:
            segments.append((start, j))
        i = j + 1
    return segments


def plot_run(result: Any, out: Path, network: RoadNetwork | None = None) -> list[Path]:
    """Write the plots of ``result`` into ``out`` (``world.png`` draws the lanes of
    ``network`` when given); returns the files written."""
    out.mkdir(parents=True, exist_ok=True)
    actors = _moving(result)
    written: list[Path] = []
    if not actors:
        return written
    title = f"{result.metadata['scenario']}: {result.outcome.status}"

    fig, (ax1, ax2) = _figure(2)
    for name, ch in actors.items():
        ax1.plot(ch["time"], ch["speed"] * KPH, label=name)
        if not np.all(np.isnan(ch["throttle"])):
            (line,) = ax2.plot(ch["time"], ch["throttle"], label=f"{name} throttle")
            ax2.plot(
                ch["time"],
                -ch["brake"],
                ls=":",
                color=line.get_color(),
                label=f"{name} brake (down)",
            )
    ax1.set(ylabel="speed (kph)", title=title)
    ax2.set(ylabel="throttle / -brake", xlabel="time (s)")
    for ax in (ax1, ax2):
        _mark_events(ax, result)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    written.append(_save(fig, out / "speed_throttle.png"))

    fig, (ax1, ax2) = _figure(2)
    for name, ch in actors.items():
        ax1.plot(ch["time"], ch["accel"], label=name, lw=0.9)
        ax2.plot(ch["time"], ch["jerk"], label=name, lw=0.9)
    ax1.set(ylabel="acceleration (m/s²)", title=f"{title}: acceleration (50 ms windows)")
    ax2.set(ylabel="jerk, 1 s filter (m/s³)", xlabel="time (s)")
    for ax in (ax1, ax2):
        _mark_events(ax, result)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    written.append(_save(fig, out / "accel_jerk.png"))

    stops = [(name, seg) for name, ch in actors.items() for seg in brake_onsets(ch)]
    if stops:
        fig, (ax,) = _figure(1)
        for name, (a, b) in stops:
            ch = actors[name]
            x, y = ch["x"][a : b + 1], ch["y"][a : b + 1]
            distance = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))))
            mu = ch["friction"][a]
            ax.plot(
                distance,
                ch["speed"][a : b + 1] * KPH,
                label=f"{name} at {ch['time'][a]:.1f} s, µ {mu:.2g}: {distance[-1]:.1f} m",
            )
        ax.set(
            xlabel="distance from brake onset (m)", ylabel="speed (kph)", title=f"{title}: stopping"
        )
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        written.append(_save(fig, out / "braking.png"))

    names = list(actors)
    if len(result.telemetry) > 1:
        fig, (ax1, ax2) = _figure(2)
        ref = result.telemetry[names[0]]
        for name, ch in result.telemetry.items():
            if name == names[0]:
                continue
            n = min(len(ch["x"]), len(ref["x"]))
            gap = (ch["x"][:n] - ref["x"][:n]) * np.cos(ref["yaw"][:n]) + (
                ch["y"][:n] - ref["y"][:n]
            ) * np.sin(ref["yaw"][:n])
            ax1.plot(ref["time"][:n], gap, label=f"{name} ahead of {names[0]}")
        for name, ch in actors.items():
            if not np.all(np.isnan(ch["steer"])):
                ax2.plot(ch["time"], ch["steer"], label=name)
        ax1.set(ylabel="longitudinal gap (m)", title=f"{title}: gap and steering")
        ax2.set(ylabel="steer (fraction of max)", xlabel="time (s)")
        for ax in (ax1, ax2):
            _mark_events(ax, result)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8, loc="lower right")
        written.append(_save(fig, out / "gap_steering.png"))
    written.append(_plot_world(result, out, title, network))
    return written


#: colours of the semantic traffic-light states in the plots
_LIGHT_COLOURS = {
    "off": "0.6",
    "stop": "red",
    "stop_attention": "darkorange",
    "attention": "gold",
    "caution": "khaki",
    "go": "green",
    "go_exclusive": "darkgreen",
    "non_functional": "purple",
}
_SEMANTIC_ORDER = list(_LIGHT_COLOURS)


_LANE_COLOURS = {"driving": "0.80", "junction": "0.70", "walking": "#efe2cf", "other": "0.92"}
MAP_MARGIN = 40.0  # m of map around the actors' paths


def _lane_polygons(network: RoadNetwork) -> dict[str, list[np.ndarray]]:
    """Every lane of the map as a polygon in the world, grouped by how it is drawn."""
    groups: dict[str, list[np.ndarray]] = {key: [] for key in _LANE_COLOURS}
    for road in network.roads.values():
        for section in road.sections:
            sl = slice(section.start, section.stop)
            x, y, h = road.x[sl], road.y[sl], road.heading[sl]
            nx, ny = -np.sin(h), np.cos(h)
            for k, lane in enumerate(section.lanes):
                left, right = section.borders[k], section.borders[k + 1]
                if np.all(left - right <= 1e-6):
                    continue
                polygon = np.concatenate(
                    (
                        np.column_stack((x + left * nx, y + left * ny)),
                        np.column_stack((x + right * nx, y + right * ny))[::-1],
                    )
                )
                if lane.drivable:
                    key = "junction" if road.junction is not None else "driving"
                elif lane.type in ("sidewalk", "walking", "biking"):
                    key = "walking"
                else:
                    key = "other"
                groups[key].append(polygon)
    return groups


def _draw_map(ax: Any, network: RoadNetwork, result: Any) -> None:
    """The map's lanes under the paths, the view set to the paths with a margin."""
    for key, polygons in _lane_polygons(network).items():
        if polygons:
            ax.add_collection(
                PolyCollection(
                    polygons, facecolors=_LANE_COLOURS[key], edgecolors="0.55", linewidths=0.3
                )
            )
    x0, x1, y0, y1 = network.bounds()
    xs = [ch["x"][np.isfinite(ch["x"])] for ch in result.telemetry.values()]
    ys = [ch["y"][np.isfinite(ch["y"])] for ch in result.telemetry.values()]
    if any(len(a) for a in xs):
        x0 = max(x0, min(float(a.min()) for a in xs if len(a)) - MAP_MARGIN)
        x1 = min(x1, max(float(a.max()) for a in xs if len(a)) + MAP_MARGIN)
        y0 = max(y0, min(float(a.min()) for a in ys if len(a)) - MAP_MARGIN)
        y1 = min(y1, max(float(a.max()) for a in ys if len(a)) + MAP_MARGIN)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)


def _plot_world(result: Any, out: Path, title: str, network: RoadNetwork | None = None) -> Path:
    """``world.png``: every actor's path in world x-y (start and end marked) over the map's
    lanes, with the traffic lights at their places in their last state; below, each
    light's state over time."""
    lights = result.metadata.get("traffic_lights") or {}
    changes: dict[str, list[tuple[float, str]]] = {name: [] for name in lights}
    for e in result.events:
        if e.kind == "traffic_light" and e.name in changes:
            changes[e.name].append((e.time, e.detail.split(" ")[0]))
    rows = 2 if lights else 1
    fig = Figure(figsize=(10, 8 + 3.2 * (rows - 1)), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(rows, 1, height_ratios=[8, 3.2][:rows])
    axes = [fig.add_subplot(grid[i, 0]) for i in range(rows)]
    ax = axes[0]
    if network is not None:
        _draw_map(ax, network, result)
    for name, ch in result.telemetry.items():
        (line,) = ax.plot(ch["x"], ch["y"], label=name, lw=1.4)
        ax.plot(ch["x"][:1], ch["y"][:1], "o", color=line.get_color(), ms=5)
        ax.plot(ch["x"][-1:], ch["y"][-1:], "s", color=line.get_color(), ms=5)
    for name, where in lights.items():
        last = changes[name][-1][1] if changes[name] else "off"
        ax.plot(
            where["x"],
            where["y"],
            "s",
            ms=9,
            color=_LIGHT_COLOURS.get(last, "0.3"),
            markeredgecolor="black",
        )
        ax.annotate(
            name, (where["x"], where["y"]), fontsize=7, xytext=(4, 4), textcoords="offset points"
        )
    where = f" on map `{network.name}`" if network is not None else ""
    ax.set(xlabel="x (m)", ylabel="y (m)", title=f"{title}: paths{where}")
    ax.set_aspect("equal", adjustable="box" if network is not None else "datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    if lights:
        ax2 = axes[1]
        end = max((float(ch["time"][-1]) for ch in result.telemetry.values()), default=0.0)
        for name, seq in changes.items():
            times = [t for t, _ in seq] + [end]
            states = [_SEMANTIC_ORDER.index(s) for _, s in seq]
            if states:
                ax2.step(times, [*states, states[-1]], where="post", label=name)
        ax2.set_yticks(range(len(_SEMANTIC_ORDER)), _SEMANTIC_ORDER, fontsize=7)
        ax2.set(xlabel="time (s)", title="traffic lights")
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize=8, loc="lower right")
    return _save(fig, out / "world.png")


def _save(fig: Figure, path: Path) -> Path:
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png")
    return path
