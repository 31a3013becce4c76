"""The report's figures of runs over parameters: pass/fail maps and KPIs over each.

* :func:`pass_fail_map`: the runs over two swept parameters. When both take few
  values (at most :data:`GRID_VALUES` each, and half as many as the runs: a
  protocol's grid), a grid of
  the share of runs passed in each cell with the counts; otherwise each run is a
  marker at its two values (passed a green circle, failure a red cross, timeout
  an orange triangle, error a purple square) over the regions where the pair's
  decision tree (:mod:`osc2runner.campaign.failures`) finds most runs failing
  (shaded red), its thresholds dashed.
* :func:`kpi_figure`: each KPI that some run has, over one swept parameter, a
  point a run coloured by its outcome.

An enum or boolean parameter is drawn at one position per value, its values as
tick labels. Every axis is labelled with the parameter and its unit; the legend
sits outside the axes. Figures are matplotlib ``Figure`` objects on the Agg
canvas; the report inlines them as PNG.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LinearSegmentedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from osc2runner.campaign.failures import grow
from osc2runner.campaign.parameters import numeric
from osc2runner.campaign.worker import RunRecord

__all__ = ["COLOURS", "GRID_VALUES", "MARKERS", "SCATTER_KPIS", "kpi_figure", "pass_fail_map"]

GRID_VALUES = 24
COLOURS = {
    "success": "#2e7d32",
    "failure": "#c62828",
    "timeout": "#ef6c00",
    "error": "#6a1b9a",
    "interrupted": "#9e9e9e",
}
MARKERS = {"success": "o", "failure": "X", "timeout": "^", "error": "s", "interrupted": "."}
SCATTER_KPIS = (
    "min_ttc_s",
    "min_gap_m",
    "relative_impact_speed_kph",
    "speed_reduction_kph",
    "max_decel_mps2",
    "time_to_stop_s",
)


def _legend(ax: Any, handles: list[Any] | None = None, labels: list[str] | None = None) -> None:
    """The axes' legend outside it, on the right."""
    if handles is None or labels is None:
        handles, labels = ax.get_legend_handles_labels()
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0),
              borderaxespad=0.0)  # fmt: skip


def figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=90, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _value(r: RunRecord, name: str) -> Any:
    return r.parameters.get(name, {}).get("value")


def _label(name: str, domains: Mapping[str, Mapping[str, Any]]) -> str:
    unit = domains.get(name, {}).get("unit") or ""
    return f"{name} ({unit})" if unit else name


def positions(
    records: Sequence[RunRecord], name: str
) -> tuple[list[float | None], list[str] | None]:
    """Where each run sits on a parameter's axis: its number, or for an enum or boolean
    the index of its value among the values (returned as tick labels)."""
    values = [_value(r, name) for r in records]
    if all(numeric(v) is not None for v in values if v is not None):
        return [numeric(v) for v in values], None
    labels = sorted({str(v) for v in values if v is not None})
    return [labels.index(str(v)) if v is not None else None for v in values], labels


def pass_fail_map(
    records: Sequence[RunRecord], x: str, y: str, domains: Mapping[str, Mapping[str, Any]]
) -> Figure:
    """The runs over ``x`` and ``y`` (see the module docstring)."""
    done = [r for r in records if r.finished]
    xs, x_labels = positions(done, x)
    ys, y_labels = positions(done, y)
    if all(_few(done, n) for n in (x, y)):
        return _grid(done, x, y, domains)
    fig = figure(7.5, 4.6)
    ax = fig.add_subplot()
    leaves, _ = grow(done, [x, y])
    x0, x1 = _limits([v for v in xs if v is not None])
    y0, y1 = _limits([v for v in ys if v is not None])
    for leaf in leaves:
        if leaf.failed <= leaf.passed or not leaf.path:
            continue
        box = {x: [x0, x1], y: [y0, y1]}
        for split, holds in leaf.path:
            if split.threshold is None:
                continue
            side = box[split.name]
            if holds:
                side[1] = min(side[1], split.threshold)
            else:
                side[0] = max(side[0], split.threshold)
        ax.add_patch(Rectangle((box[x][0], box[y][0]), box[x][1] - box[x][0],
                               box[y][1] - box[y][0], color="#ffcdd2", alpha=0.6, lw=0,
                               gid="failure-region", label="most runs fail here"))  # fmt: skip
    drawn: set[tuple[str, float]] = set()
    for leaf in leaves:
        for split, _ in leaf.path:
            if split.threshold is None or (split.name, split.threshold) in drawn:
                continue
            drawn.add((split.name, split.threshold))
            line = ax.axvline if split.name == x else ax.axhline
            line(split.threshold, color="#c62828", ls="--", lw=1.0, gid="threshold")
    for status, colour in COLOURS.items():
        pts = [
            (a, b)
            for r, a, b in zip(done, xs, ys, strict=True)
            if r.status == status and a is not None and b is not None
        ]
        if pts:
            px, py = zip(*pts, strict=True)
            ax.scatter(px, py, s=36, color=colour, marker=MARKERS[status], label=status,
                       gid=f"runs-{status}", edgecolors="none")  # fmt: skip
    if x_labels is not None:
        ax.set_xticks(range(len(x_labels)), x_labels)
    if y_labels is not None:
        ax.set_yticks(range(len(y_labels)), y_labels)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set(xlabel=_label(x, domains), ylabel=_label(y, domains),
           title=f"runs over {x} and {y}")  # fmt: skip
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    _legend(ax, list(unique.values()), list(unique))
    return fig


def _few(records: Sequence[RunRecord], name: str) -> bool:
    """Whether a parameter takes few values: at most :data:`GRID_VALUES`, each run's
    shared with another's on average."""
    distinct = len({str(_value(r, name)) for r in records})
    return distinct <= GRID_VALUES and 2 * distinct <= len(records)


def _limits(values: list[float]) -> tuple[float, float]:
    if not values:
        return (0.0, 1.0)
    low, high = min(values), max(values)
    pad = 0.05 * (high - low) if high > low else 0.5
    return (low - pad, high + pad)


def _grid(
    records: Sequence[RunRecord], x: str, y: str, domains: Mapping[str, Mapping[str, Any]]
) -> Figure:
    """Pass rate over two parameters of few values each: runs passed / runs per cell."""
    xs = _ordered([_value(r, x) for r in records])
    ys = _ordered([_value(r, y) for r in records])
    passed = np.zeros((len(ys), len(xs)))
    total = np.zeros((len(ys), len(xs)))
    for r in records:
        a, b = _value(r, x), _value(r, y)
        if a in xs and b in ys:
            total[ys.index(b), xs.index(a)] += 1
            passed[ys.index(b), xs.index(a)] += r.passed
    rate = np.where(total > 0, passed / np.maximum(total, 1), np.nan)
    fig = figure(min(12.0, 2.5 + 0.75 * len(xs)), 1.4 + 0.45 * len(ys))
    ax = fig.add_subplot()
    cmap = LinearSegmentedColormap.from_list(
        "pass", ["#c62828", "#fdd835", "#2e7d32"]
    ).with_extremes(bad="#eeeeee")
    image = ax.imshow(rate, cmap=cmap, vmin=0, vmax=1, aspect="auto", origin="lower",
                      gid="pass-rate")  # fmt: skip
    for j in range(len(ys)):
        for i in range(len(xs)):
            if total[j, i]:
                ax.text(i, j, f"{int(passed[j, i])}/{int(total[j, i])}", ha="center",
                        va="center", fontsize=8, color="black")  # fmt: skip
    ax.set_xticks(range(len(xs)), [str(v) for v in xs])
    ax.set_yticks(range(len(ys)), [str(v) for v in ys])
    ax.set(xlabel=_label(x, domains), ylabel=_label(y, domains),
           title=f"runs passed / runs over {x} and {y} (grey: not run)")  # fmt: skip
    fig.colorbar(image, ax=ax, label="share of runs passed")
    return fig


def _ordered(values: list[Any]) -> list[Any]:
    distinct = {v for v in values if v is not None}
    if all(numeric(v) is not None for v in distinct):
        return sorted(distinct, key=float)
    return sorted(distinct, key=str)


def kpis_of(records: Sequence[RunRecord]) -> list[str]:
    """The scatter KPIs some run has a number for."""
    return [k for k in SCATTER_KPIS if any(numeric(r.kpis.get(k)) is not None for r in records)]


def kpi_figure(
    records: Sequence[RunRecord], name: str, domains: Mapping[str, Mapping[str, Any]]
) -> Figure | None:
    """Each KPI over the swept parameter ``name`` (see the module docstring); None when
    no run has a KPI to show."""
    done = [r for r in records if r.finished]
    kpis = kpis_of(done)
    if not kpis:
        return None
    where, labels = positions(done, name)
    cols = min(3, len(kpis))
    rows = -(-len(kpis) // cols)
    fig = figure(3.7 * cols + 1.4, 2.5 * rows + 0.4)
    fig.suptitle(f"KPIs over {name}")
    for i, kpi in enumerate(kpis):
        ax = fig.add_subplot(rows, cols, i + 1)
        for status, colour in COLOURS.items():
            pts = [
                (w, float(r.kpis[kpi]))
                for r, w in zip(done, where, strict=True)
                if r.status == status and w is not None and numeric(r.kpis.get(kpi)) is not None
            ]
            if pts:
                px, py = zip(*pts, strict=True)
                ax.scatter(px, py, s=16, color=colour, label=status, marker=MARKERS[status],
                           gid=f"{kpi}-{status}")  # fmt: skip
        if labels is not None:
            ax.set_xticks(range(len(labels)), labels)
        ax.set_xlabel(_label(name, domains), fontsize=8)
        ax.set_ylabel(kpi, fontsize=8)
        ax.grid(alpha=0.3)
    found = dict(
        (label, handle)
        for ax in fig.axes
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True)
    )
    _legend(fig.axes[cols - 1], list(found.values()), list(found))
    return fig
