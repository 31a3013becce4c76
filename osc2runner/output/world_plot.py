"""``world.png``: a bird's-eye view of a run, zoomed to where the actors went.

The map's lanes (driving lanes grey, junction roads darker, sidewalks and other lane
types paler) under every actor's path: its start a circle, its end a square, dots at
whole times along it (every 1, 2, 5, 10, ... s, so about ten of them; the subject's
labelled with the time), a red cross where it collided; the traffic lights in their
last state. The view is the paths with a margin of a tenth of their extent (at least
:data:`MIN_MARGIN`), its shorter side widened to keep its proportions within
:data:`RATIOS`, and the figure takes the view's proportions, so a straight road is
drawn as a strip, not as a line on a blank page. Below, when the scenario has
traffic lights, each light's semantic state over time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from osc2check.world.network import RoadNetwork

__all__ = ["MIN_MARGIN", "TIME_STEPS", "time_step", "view", "world_figure"]

MIN_MARGIN = 5.0  # m of map around the actors' paths, at least
TIME_STEPS = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0)  # s between dots
WIDTH = 10.0  # in: the figure's width; its height follows the view
RATIOS = (0.25, 0.9)  # the view's height over its width, at least and at most
_LANE_COLOURS = {"driving": "0.80", "junction": "0.70", "walking": "#efe2cf", "other": "0.92"}
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


def time_step(duration: float) -> float:
    """The step between time dots: the smallest of :data:`TIME_STEPS` that gives at most
    ten dots over ``duration``."""
    return next((s for s in TIME_STEPS if duration / s <= 10.0), TIME_STEPS[-1])


def view(telemetry: dict[str, dict[str, np.ndarray]]) -> tuple[float, float, float, float]:
    """``(x0, x1, y0, y1)``: the actors' paths with their margin, the shorter side widened
    about its middle to keep the view's height between :data:`RATIOS` of its width."""
    xs = [ch["x"][np.isfinite(ch["x"])] for ch in telemetry.values()]
    ys = [ch["y"][np.isfinite(ch["y"])] for ch in telemetry.values()]
    xs, ys = [a for a in xs if len(a)], [a for a in ys if len(a)]
    if not xs or not ys:
        return (-MIN_MARGIN, MIN_MARGIN, -MIN_MARGIN, MIN_MARGIN)
    x0, x1 = min(float(a.min()) for a in xs), max(float(a.max()) for a in xs)
    y0, y1 = min(float(a.min()) for a in ys), max(float(a.max()) for a in ys)
    margin = max(MIN_MARGIN, 0.1 * max(x1 - x0, y1 - y0))
    x0, x1, y0, y1 = x0 - margin, x1 + margin, y0 - margin, y1 + margin
    low, high = RATIOS
    if y1 - y0 < low * (x1 - x0):
        half = 0.5 * low * (x1 - x0)
        y0, y1 = 0.5 * (y0 + y1) - half, 0.5 * (y0 + y1) + half
    elif y1 - y0 > high * (x1 - x0):
        half = 0.5 * (y1 - y0) / high
        x0, x1 = 0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half
    return (x0, x1, y0, y1)


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


def _draw_map(ax: Any, network: RoadNetwork) -> None:
    for key, polygons in _lane_polygons(network).items():
        if polygons:
            ax.add_collection(
                PolyCollection(
                    polygons, facecolors=_LANE_COLOURS[key], edgecolors="0.55", linewidths=0.3
                )
            )


def _light_changes(result: Any) -> dict[str, list[tuple[float, str]]]:
    lights = result.metadata.get("traffic_lights") or {}
    changes: dict[str, list[tuple[float, str]]] = {name: [] for name in lights}
    for e in result.events:
        if e.kind == "traffic_light" and e.name in changes:
            changes[e.name].append((e.time, e.detail.split(" ")[0]))
    return changes


def world_figure(
    result: Any, title: str, network: RoadNetwork | None = None, subject: str | None = None
) -> Figure:
    """The figure of ``world.png`` (see the module docstring); ``subject``'s time dots
    are labelled."""
    lights = result.metadata.get("traffic_lights") or {}
    changes = _light_changes(result)
    x0, x1, y0, y1 = view(result.telemetry)
    map_height = WIDTH * (y1 - y0) / (x1 - x0)
    rows = 2 if lights else 1
    heights = [map_height + 0.9, 3.2][:rows]
    fig = Figure(figsize=(WIDTH, sum(heights)), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(rows, 1, height_ratios=heights)
    ax = fig.add_subplot(grid[0, 0])
    if network is not None:
        _draw_map(ax, network)
    _draw_paths(ax, result, subject)
    for name, where in lights.items():
        last = changes[name][-1][1] if changes[name] else "off"
        ax.plot(where["x"], where["y"], "s", ms=9, color=_LIGHT_COLOURS.get(last, "0.3"),
                markeredgecolor="black", gid="traffic-light")  # fmt: skip
        ax.annotate(
            name, (where["x"], where["y"]), fontsize=7, xytext=(4, 4), textcoords="offset points"
        )
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    where = f" on map `{network.name}`" if network is not None else ""
    ax.set(xlabel="x (m)", ylabel="y (m)", title=f"{title}: paths{where}")
    ax.set_aspect("equal", adjustable="box")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0.0)
    if lights:
        _draw_lights(fig.add_subplot(grid[1, 0]), result, changes)
    return fig


def _draw_paths(ax: Any, result: Any, subject: str | None) -> None:
    """Each actor's path with its start, end, time dots and collision points."""
    ends = [float(ch["time"][-1]) for ch in result.telemetry.values() if len(ch["time"])]
    step = time_step(max(ends, default=0.0))
    collided: dict[str, list[tuple[int, float, bool]]] = {}  # tick, time, labelled here
    for e in result.events:
        if e.kind == "collision":
            for k, actor in enumerate(e.actors):
                collided.setdefault(actor, []).append((e.tick, e.time, k == 0))
    for name, ch in result.telemetry.items():
        x, y, time = ch["x"], ch["y"], ch["time"]
        if not len(x):
            continue
        (line,) = ax.plot(x, y, label=name, lw=1.4)
        colour = line.get_color()
        ax.plot(x[:1], y[:1], "o", color=colour, ms=5, gid="start")
        ax.plot(x[-1:], y[-1:], "s", color=colour, ms=5, gid="end")
        marks = np.arange(step, float(time[-1]) + 1e-9, step)
        rows = np.searchsorted(time, marks - 1e-9)
        rows = rows[rows < len(time)]
        ax.plot(x[rows], y[rows], ".", color=colour, ms=6, gid="time-dot")
        if name == subject:
            for row in rows:
                ax.annotate(f"{time[row]:g} s", (x[row], y[row]), fontsize=7, color=colour,
                            xytext=(0, 6), textcoords="offset points", ha="center")  # fmt: skip
        for tick, when, labelled in collided.get(name, []):
            row = min(int(np.searchsorted(ch["tick"], tick)), len(x) - 1)
            ax.plot(x[row], y[row], "X", color="red", ms=11, markeredgecolor="black",
                    gid="collision")  # fmt: skip
            if labelled:
                ax.annotate(f"collision at {when:g} s", (x[row], y[row]), fontsize=7,
                            color="red", xytext=(0, -14), textcoords="offset points",
                            ha="center")  # fmt: skip


def _draw_lights(ax: Any, result: Any, changes: dict[str, list[tuple[float, str]]]) -> None:
    end = max((float(ch["time"][-1]) for ch in result.telemetry.values()), default=0.0)
    for name, seq in changes.items():
        times = [t for t, _ in seq] + [end]
        states = [_SEMANTIC_ORDER.index(s) for _, s in seq]
        if states:
            ax.step(times, [*states, states[-1]], where="post", label=name)
    ax.set_yticks(range(len(_SEMANTIC_ORDER)), _SEMANTIC_ORDER, fontsize=7)
    ax.set(xlabel="time (s)", title="traffic lights")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0.0)
