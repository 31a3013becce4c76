"""``report.html``: one self-contained page that says what a campaign found.

Sections: the summary (scenario, strategy, system under test, outcomes, pass
rate, time); the pass criterion and, when two parameters vary, a heat map of
the runs that passed over both (which speeds and overlaps fail); the coverage
of every ``cover`` item (hits per bucket, holes, unreachable buckets); the KPIs
over each varying parameter (scatter, coloured by outcome) and their figures;
the worst runs; every run. Images are PNGs drawn with matplotlib and inlined
(``data:`` URIs), so the file opens anywhere alone; each run links to its own
files (``runs/<seed>/``: plots, telemetry, ``run.json``) beside it.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from osc2runner.campaign.summary import axes, worst_runs
from osc2runner.campaign.worker import RunRecord
from osc2runner.export import FILE_NAMES
from osc2runner.output.files import write_atomically

__all__ = ["REPORT_FILE", "write_report"]

REPORT_FILE = "report.html"
COLOURS = {
    "success": "#2e7d32",
    "failure": "#c62828",
    "timeout": "#ef6c00",
    "error": "#6a1b9a",
    "interrupted": "#9e9e9e",
}
SCATTER_KPIS = (
    "min_ttc_s",
    "min_gap_m",
    "relative_impact_speed_kph",
    "speed_reduction_kph",
    "max_decel_mps2",
    "time_to_stop_s",
)
_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:24px auto;
max-width:1180px;color:#212121;line-height:1.4;padding:0 16px}
h1{font-size:1.6em;margin-bottom:4px}h2{margin-top:32px;border-bottom:2px solid #e0e0e0;
padding-bottom:4px}.sub{color:#616161}.cards{display:flex;gap:12px;flex-wrap:wrap;margin:16px 0}
.card{border:1px solid #e0e0e0;border-radius:8px;padding:10px 16px;min-width:110px}
.card b{display:block;font-size:1.5em}.card span{color:#616161;font-size:.85em}
table{border-collapse:collapse;font-size:.85em;margin:8px 0}td,th{border:1px solid #e0e0e0;
padding:3px 7px;text-align:left;vertical-align:top}th{background:#f5f5f5}
.st{font-weight:600}.success{color:#2e7d32}.failure{color:#c62828}.timeout{color:#ef6c00}
.error{color:#6a1b9a}.interrupted{color:#9e9e9e}code{font-size:.9em;background:#f5f5f5;
padding:1px 3px;border-radius:3px}img{max-width:100%}.note{color:#616161;font-size:.9em}
.hole{background:#ffebee}.unreachable{background:#eeeeee;color:#9e9e9e}
details summary{cursor:pointer;color:#1565c0}
"""


def _e(value: Any) -> str:
    return html.escape("" if value is None else str(value))


def _png(fig: Any) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<img alt="" src="data:image/png;base64,{data}">'


def preload() -> None:
    """Import the plotting modules ahead of the report (the campaign does it on a thread
    of its own while its runs go on: matplotlib takes seconds to import)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: F401
    from matplotlib.figure import Figure  # noqa: F401


def _figure(width: float, height: float) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=90, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _axis_values(records: Sequence[RunRecord], name: str) -> list[Any]:
    return [r.parameters.get(name, {}).get("value") for r in records]


def _ordered(values: list[Any]) -> list[Any]:
    distinct = {v for v in values if v is not None}
    if all(_number(v) is not None for v in distinct):
        return sorted(distinct, key=float)
    return sorted(distinct, key=str)


def _grid(records: Sequence[RunRecord], params: list[str]) -> str:
    """Pass rate over two parameters (the first two with few distinct values)."""
    few = [p for p in params if 1 < len(set(map(str, _axis_values(records, p)))) <= 24][:2]
    if len(few) < 2:
        return ""
    x_name, y_name = few[0], few[1]
    xs, ys = _ordered(_axis_values(records, x_name)), _ordered(_axis_values(records, y_name))
    import numpy as np

    passed = np.zeros((len(ys), len(xs)))
    total = np.zeros((len(ys), len(xs)))
    for r in records:
        x = r.parameters.get(x_name, {}).get("value")
        y = r.parameters.get(y_name, {}).get("value")
        if x in xs and y in ys:
            total[ys.index(y), xs.index(x)] += 1
            passed[ys.index(y), xs.index(x)] += r.passed
    rate = np.where(total > 0, passed / np.maximum(total, 1), np.nan)
    fig = _figure(min(11.0, 1.0 + 0.75 * len(xs)), 1.2 + 0.5 * len(ys))
    ax = fig.add_subplot()
    from matplotlib.colors import LinearSegmentedColormap

    cmap = LinearSegmentedColormap.from_list(
        "pass", ["#c62828", "#fdd835", "#2e7d32"]
    ).with_extremes(bad="#eeeeee")
    image = ax.imshow(rate, cmap=cmap, vmin=0, vmax=1, aspect="auto", origin="lower")
    for j in range(len(ys)):
        for i in range(len(xs)):
            if total[j, i]:
                ax.text(i, j, f"{int(passed[j, i])}/{int(total[j, i])}", ha="center",
                        va="center", fontsize=8, color="black")  # fmt: skip
    ax.set_xticks(range(len(xs)), [str(v) for v in xs])
    ax.set_yticks(range(len(ys)), [str(v) for v in ys])
    unit_x = records[0].parameters.get(x_name, {}).get("unit") or ""
    unit_y = records[0].parameters.get(y_name, {}).get("unit") or ""
    ax.set_xlabel(f"{x_name} {('(' + unit_x + ')') if unit_x else ''}")
    ax.set_ylabel(f"{y_name} {('(' + unit_y + ')') if unit_y else ''}")
    fig.colorbar(image, ax=ax, label="runs passed")
    return (
        f"<p>Runs passed / runs, over <code>{_e(x_name)}</code> and "
        f"<code>{_e(y_name)}</code> (grey: not run).</p>" + _png(fig)
    )


def _coverage(document: dict[str, Any]) -> str:
    items = document.get("coverage", [])
    if not items:
        return "<p>The scenario has no <code>cover</code> item with buckets.</p>"
    parts = []
    for item in items:
        buckets = item["buckets"]
        split = [b["label"].split(" × ") for b in buckets]
        if buckets and all(len(p) == 2 for p in split):
            parts.append(_cross_map(item, split))
            continue
        fig = _figure(min(11.0, 1.5 + 0.55 * len(buckets)), 1.6)
        ax = fig.add_subplot()
        hits = [b["hits"] for b in buckets]
        colours = [
            "#bdbdbd"
            if b["state"] == "unreachable"
            else ("#ef9a9a" if not b["hits"] else "#1565c0")
            for b in buckets
        ]
        ax.bar(range(len(buckets)), hits, color=colours)
        ax.set_xticks(range(len(buckets)), [b["label"] for b in buckets], rotation=30,
                      ha="right", fontsize=7)  # fmt: skip
        ax.set_ylabel("runs")
        for i, b in enumerate(buckets):
            if b["state"] != "filled":
                ax.text(i, 0, "unreachable" if b["state"] == "unreachable" else "hole",
                        rotation=90, ha="center", va="bottom", fontsize=7)  # fmt: skip
        steer = (
            "steered by the solver"
            if item["steerable"]
            else f"observed only: {_e(item['reason'] or 'not steerable')}"
        )
        holes = ", ".join(item["holes"]) or "none"
        parts.append(
            f"<h3><code>{_e(item['name'])}</code>: {item['filled']} of {item['reachable']} "
            f"reachable buckets filled</h3><p class='note'>{steer}; holes: {_e(holes)}; "
            f"unreachable (no instance of the scenario lands there): {item['unreachable']}</p>"
            + _png(fig)
        )
    return "".join(parts)


def _cross_map(item: dict[str, Any], split: list[list[str]]) -> str:
    """A cross item of two: runs per combination, as a grid (grey: unreachable)."""
    import numpy as np

    xs = list(dict.fromkeys(p[0] for p in split))
    ys = list(dict.fromkeys(p[1] for p in split))
    hits = np.full((len(ys), len(xs)), np.nan)
    for (x, y), b in zip(split, item["buckets"], strict=True):
        if b["state"] != "unreachable":
            hits[ys.index(y), xs.index(x)] = b["hits"]
    fig = _figure(min(11.0, 1.5 + 0.75 * len(xs)), 1.2 + 0.4 * len(ys))
    ax = fig.add_subplot()
    from matplotlib.colors import LinearSegmentedColormap

    cmap = LinearSegmentedColormap.from_list("hits", ["#ffcdd2", "#1565c0"]).with_extremes(
        bad="#eeeeee"
    )
    ax.imshow(hits, cmap=cmap, vmin=0, vmax=max(1.0, float(np.nanmax(hits, initial=1.0))),
              aspect="auto", origin="lower")  # fmt: skip
    for j in range(len(ys)):
        for i in range(len(xs)):
            if not np.isnan(hits[j, i]):
                ax.text(i, j, f"{int(hits[j, i])}", ha="center", va="center", fontsize=8)
    ax.set_xticks(range(len(xs)), xs, rotation=30, ha="right", fontsize=7)
    ax.set_yticks(range(len(ys)), ys, fontsize=7)
    holes = ", ".join(item["holes"]) or "none"
    return (
        f"<h3><code>{_e(item['name'])}</code> (cross): {item['filled']} of {item['reachable']} "
        f"reachable combinations filled</h3><p class='note'>runs per combination; grey: "
        f"unreachable ({item['unreachable']}); holes: {_e(holes)}</p>" + _png(fig)
    )


def _scatter(records: Sequence[RunRecord], params: list[str]) -> str:
    numeric = [p for p in params if all(
        _number(v) is not None for v in _axis_values(records, p) if v is not None)][:3]  # fmt: skip
    kpis = [k for k in SCATTER_KPIS if any(_number(r.kpis.get(k)) is not None for r in records)]
    if not numeric or not kpis:
        return "<p>No numeric parameter varies between the runs.</p>"
    fig = _figure(3.6 * len(numeric) + 0.5, 2.3 * len(kpis))
    for row, kpi in enumerate(kpis):
        for col, param in enumerate(numeric):
            ax = fig.add_subplot(len(kpis), len(numeric), row * len(numeric) + col + 1)
            for status, colour in COLOURS.items():
                pts = [
                    (float(r.parameters[param]["value"]), float(r.kpis[kpi]))
                    for r in records
                    if r.status == status
                    and param in r.parameters
                    and _number(r.parameters[param].get("value")) is not None
                    and _number(r.kpis.get(kpi)) is not None
                ]
                if pts:
                    ax.scatter(*zip(*pts, strict=True), s=14, color=colour, label=status,
                               alpha=0.8)  # fmt: skip
            unit = records[0].parameters.get(param, {}).get("unit")
            if row == len(kpis) - 1:
                ax.set_xlabel(f"{param}" + (f" ({unit})" if unit else ""))
            if col == 0:
                ax.set_ylabel(f"{kpi}", fontsize=8)
            ax.grid(alpha=0.3)
            if row == 0 and col == len(numeric) - 1:
                ax.legend(fontsize=7)
    return _png(fig)


def _histograms(records: Sequence[RunRecord]) -> str:
    """The distribution of each KPI over the runs, coloured by outcome."""
    kpis = [k for k in SCATTER_KPIS if any(_number(r.kpis.get(k)) is not None for r in records)]
    if not kpis:
        return ""
    cols = min(3, len(kpis))
    rows = math.ceil(len(kpis) / cols)
    fig = _figure(3.6 * cols + 0.5, 2.3 * rows)
    for i, kpi in enumerate(kpis):
        ax = fig.add_subplot(rows, cols, i + 1)
        groups, colours, labels = [], [], []
        for status, colour in COLOURS.items():
            values = [float(r.kpis[kpi]) for r in records
                      if r.status == status and _number(r.kpis.get(kpi)) is not None]  # fmt: skip
            if values:
                groups.append(values)
                colours.append(colour)
                labels.append(status)
        ax.hist(groups, bins=12, stacked=True, color=colours, label=labels)
        ax.set_xlabel(kpi, fontsize=8)
        ax.set_ylabel("runs", fontsize=8)
        if i == 0:
            ax.legend(fontsize=7)
    return _png(fig)


def _links(r: RunRecord, folder: Path) -> str:
    run_dir = folder / r.folder
    names = sorted(p.name for p in run_dir.glob("*.png"))  # the run's plots, whichever it has
    names += [n for n in ("run.json", "telemetry.csv", "events.csv") if (run_dir / n).is_file()]
    names += [n for n in FILE_NAMES.values() if (run_dir / n).is_file()]  # exports (--export)
    return " ".join(f'<a href="{_e(r.folder)}/{_e(n)}">{_e(n.split(".")[0])}</a>' for n in names)


def _kpi_cell(r: RunRecord, name: str) -> str:
    value = r.kpis.get(name)
    if isinstance(value, bool):
        return "yes" if value else "no"
    return "" if value is None else _e(value)


def _runs_table(records: Sequence[RunRecord], params: list[str], folder: Path,
                replay: dict[int, str]) -> str:  # fmt: skip
    shown_kpis = ["collision", "relative_impact_speed_kph", "min_ttc_s", "min_gap_m",
                  "max_decel_mps2"]  # fmt: skip
    head = "".join(f"<th>{_e(p)}</th>" for p in params) + "".join(
        f"<th>{_e(k)}</th>" for k in shown_kpis
    )
    rows = []
    for r in records:
        cells = "".join(f"<td>{_e(r.parameters.get(p, {}).get('text'))}</td>" for p in params)
        cells += "".join(f"<td>{_kpi_cell(r, k)}</td>" for k in shown_kpis)
        rows.append(
            f"<tr><td>{r.seed}</td><td>{_e(r.bin.text if r.bin else '')}</td>"
            f"<td class='st {r.status}'>{r.status}</td><td>{_e(r.reason)}</td>{cells}"
            f"<td>{_links(r, folder)}</td>"
            f"<td><code>{_e(replay.get(r.seed, ''))}</code></td></tr>"
        )
    return (
        f"<table><tr><th>seed</th><th>bin</th><th>outcome</th><th>reason</th>{head}"
        f"<th>files</th><th>replay alone</th></tr>{''.join(rows)}</table>"
    )


def _shown(target: str) -> str:
    """A SUT's file path relative to the current folder when it lies below it."""
    module, _, name = target.rpartition(":")
    try:
        return f"{Path(module).relative_to(Path.cwd())}:{name}"
    except ValueError:
        return target


def write_report(folder: Path, document: dict[str, Any], records: Sequence[RunRecord]) -> Path:
    """Write ``report.html`` for the campaign ``document`` (campaign.json's content)."""
    summary = document["summary"]
    options = document["options"]
    done = [r for r in records if r.finished]
    params = axes(done, [item["name"] for item in document.get("coverage", [])])
    replay = {run["seed"]: run.get("replay", "") for run in document.get("runs", [])}
    rate = summary["pass_rate"]
    sut = options.get("sut")
    cards = [
        ("runs", f"{summary['finished']} / {len(document['plan']['seeds'])}"),
        ("passed", summary["passed"]),
        ("failed", summary["failed"]),
        ("pass rate", "–" if rate is None else f"{100 * rate:.0f} %"),
        ("collisions", summary["collisions"]),
        ("runs / min", document.get("runs_per_minute") or "–"),
    ]
    outcome_rows = "".join(
        f"<tr><td class='st {_e(k)}'>{_e(k)}</td><td>{v}</td></tr>"
        for k, v in summary["outcomes"].items()
    )
    kpi_rows = "".join(
        f"<tr><td>{_e(k)}</td><td>{_e(v['unit'])}</td><td>{v['min']}</td><td>{v['median']}</td>"
        f"<td>{v['mean']}</td><td>{v['max']}</td><td>{v['runs']}</td></tr>"
        for k, v in document.get("kpis", {}).items()
    )
    worst = worst_runs(done, 10)
    status_note = (
        "" if document["status"] == "complete"
        else f"<p class='failure'>The campaign was <b>{_e(document['status'])}</b>: "
        f"{len(document.get('not_run', []))} planned runs did not finish "
        f"(<code>osc2run --resume {_e(folder)}</code> does them).</p>"
    )  # fmt: skip
    body = f"""
<h1>Campaign: <code>{_e(document["scenario"])}</code></h1>
<p class="sub">{_e(document["source"])} · strategy <b>{_e(options["strategy"])}</b> from seed
{options["seed"]} · engine {_e(options["engine"])}, {options["jobs"]} workers ·
system under test: {
        _e(_shown(sut["target"]) + " driving " + (sut["actor"] or "sut/ego"))
        if sut
        else "none (the scenario drives every actor)"
    } · {_e(document.get("started"))},
{document.get("wall_seconds")} s</p>
{status_note}
<div class="cards">{
        "".join(f'<div class="card"><b>{_e(v)}</b><span>{_e(k)}</span></div>' for k, v in cards)
    }</div>
<h2>Pass criterion</h2>
<p>A run passes when its outcome is <span class="success">success</span>: the scenario's
behaviour ended, with no collision (unless <code>avoid_collisions(false)</code> allows it), no
actor off the road, no phase over its <code>duration</code>. Crash-test protocols grade a test
with an impact by its impact speed: <code>relative_impact_speed_kph</code> (the closing speed at
the first contact) and <code>speed_reduction_kph</code> (the start speed less the speed at
impact; all of it when there was none) are in every run's KPIs.</p>
<table><tr><th>outcome</th><th>runs</th></tr>{outcome_rows}</table>
{_grid(done, params)}
<h2>Coverage</h2>{_coverage(document)}
<h2>KPIs over the parameters</h2>{_scatter(done, params)}
<h3>Distributions</h3>{_histograms(done)}
<table><tr><th>KPI</th><th>unit</th><th>min</th><th>median</th><th>mean</th><th>max</th>
<th>runs</th></tr>{kpi_rows}</table>
<p class="note">KPIs are of the subject: the system under test's actor, else the field named
<code>sut</code> or <code>ego</code>, else the first vehicle (docs/campaigns.md).</p>
<h2>Worst runs</h2>{_runs_table(worst, params, folder, replay)}
<h2>All runs</h2><details><summary>{len(records)} runs</summary>
{_runs_table(records, params, folder, replay)}</details>
"""
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>osc2run campaign: {_e(document['scenario'])}</title>"
        f"<style>{_CSS}</style></head><body>{body}</body></html>\n"
    )
    return write_atomically(folder / REPORT_FILE, page)
