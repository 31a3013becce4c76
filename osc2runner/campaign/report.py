"""``report.html``: one self-contained page that says what a campaign found.

Sections (each with an anchor, listed at the top): the summary (scenario,
strategy, system under test, outcomes, pass rate, time); the pass criterion;
the parameters the campaign swept, how evenly its runs cover each (a warning
for one that piles up) and those that follow from them; where runs fail: the
pass/fail map over the pair of swept parameters that best separates the
failures (the other pairs one click away), the failure boundary and the triage
table (one row per group of failures alike in reason and region, with a
representative run and the command that replays it); the coverage of every
``cover`` item (hits per bucket, holes, unreachable buckets); the KPIs over each
swept parameter and their distributions; the worst runs; every run. Every run
table has a column per swept parameter. Images are PNGs drawn with matplotlib
(:mod:`osc2runner.campaign.charts`) and inlined (``data:`` URIs), each in a
``figure`` with its caption, so the file opens anywhere alone; each run links to
its own files (``runs/<seed>/``: plots, telemetry, ``run.json``) beside it.
"""

from __future__ import annotations

import base64
import html
import io
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from osc2runner.campaign.charts import COLOURS, kpi_figure, kpis_of, pass_fail_map
from osc2runner.campaign.parameters import compact_text, numeric
from osc2runner.campaign.schema import file_name
from osc2runner.campaign.summary import worst_runs
from osc2runner.campaign.worker import RunRecord
from osc2runner.export import FILE_NAMES
from osc2runner.output.files import write_atomically

__all__ = ["REPORT_FILE", "write_report"]

REPORT_FILE = "report.html"
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
details summary{cursor:pointer;color:#1565c0}.scroll{overflow-x:auto;max-width:100%}
td code{overflow-wrap:anywhere}figure{margin:10px 0}figcaption{color:#616161;font-size:.85em}
.warn{background:#fff3e0;border-left:4px solid #ef6c00;padding:4px 8px}nav a{margin-right:10px}
"""


def _e(value: Any) -> str:
    return html.escape("" if value is None else str(value))


def _png(fig: Any, caption: str) -> str:
    """The figure as an inlined PNG in a ``figure``, ``caption`` its alt text and caption."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return (
        f'<figure><img alt="{_e(caption)}" src="data:image/png;base64,{data}">'
        f"<figcaption>{_e(caption)}</figcaption></figure>"
    )


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
            + _png(fig, f"runs per bucket of the cover item {item['name']}")
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
        f"unreachable ({item['unreachable']}); holes: {_e(holes)}</p>"
        + _png(fig, f"runs per combination of the cross item {item['name']}")
    )


def _histograms(records: Sequence[RunRecord]) -> str:
    """The distribution of each KPI over the runs, coloured by outcome."""
    kpis = kpis_of(records)
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
                      if r.status == status and numeric(r.kpis.get(kpi)) is not None]  # fmt: skip
            if values:
                groups.append(values)
                colours.append(colour)
                labels.append(status)
        ax.hist(groups, bins=12, stacked=True, color=colours, label=labels)
        ax.set_xlabel(kpi, fontsize=8)
        ax.set_ylabel("runs", fontsize=8)
        if i == 0:
            ax.legend(fontsize=7)
    return _png(fig, "each KPI's distribution over the runs, stacked by outcome")


def _links(r: RunRecord, folder: Path) -> str:
    """Links to the files the run wrote (its record's, there now): its plots, whichever
    it has, then its data and exports. A file the run did not write (one that was in
    the folder before) is not linked; every link stays inside the run's folder."""
    run_dir = folder / r.folder
    wrote = {n for n in r.files if file_name(n) and (run_dir / n).is_file()}
    names = sorted(n for n in wrote if n.endswith(".png"))
    names += [n for n in ("run.json", "telemetry.csv", "events.csv", *FILE_NAMES.values())]
    return " ".join(
        f'<a href="{_e(r.folder)}/{_e(n)}">{_e(n.split(".")[0])}</a>' for n in names if n in wrote
    )


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
            f"<td class='st {_e(r.status)}'>{_e(r.status)}</td><td>{_e(r.reason)}</td>{cells}"
            f"<td>{_links(r, folder)}</td>"
            f"<td><code>{_e(replay.get(r.seed, ''))}</code></td></tr>"
        )
    return (
        f"<div class='scroll'><table><tr><th>seed</th><th>bin</th><th>outcome</th><th>reason</th>"
        f"{head}<th>files</th><th>replay alone</th></tr>{''.join(rows)}</table></div>"
    )


def _parameters(document: dict[str, Any]) -> str:
    """The swept parameters' spreads (a warning for each that piles up), and those that
    follow from them."""
    parameters = document.get("parameters", {})
    spread = parameters.get("spread", [])
    if not spread:
        return "<p>No parameter varies between the runs.</p>"
    rows, warnings = [], []
    for item in spread:
        unit = _e(item["unit"])
        if item["kind"] == "continuous":
            where = f"[{item['low']:g} .. {item['high']:g}] {unit} ({_e(item['range'])})"
            evenness = (
                f"KS D = {item['ks']:.2f} (p = {item['ks_p']:.2g})"
                if item["ks"] is not None
                else ""
            )
            bounds = f"{item['on_low']} / {item['on_high']}"
        else:
            where = f"{item['allowed']} values, {item['hit']} hit"
            evenness, bounds = "", "–"
        top = f"{_e(compact_text(item['top_value'], ' ' + item['unit']))}: {item['top_runs']}"
        rows.append(
            f"<tr><td><code>{_e(item['name'])}</code></td><td>{where}</td><td>{bounds}</td>"
            f"<td>{top} of {item['runs']}</td><td>{evenness}</td>"
            f"<td>{'piles up' if item['piles'] else 'spread'}</td></tr>"
        )
        if item["warning"]:
            warnings.append(f"<p class='warn'>{_e(item['warning'])}: the runs do not cover what "
                            "the constraints allow.</p>")  # fmt: skip
    derived = "".join(
        f"<li><code>{_e(name)}</code> {_CODE.sub(_AS_CODE, _e(why))}</li>"
        for name, why in parameters.get("derived", {}).items()
    )
    return (
        "".join(warnings)
        + "<div class='scroll'><table><tr><th>swept parameter</th><th>range</th><th>runs on "
        "the lower / upper bound</th><th>most runs at one value</th><th>uniform over its "
        "range (Kolmogorov-Smirnov)</th><th>spread</th></tr>"
        + "".join(rows)
        + "</table></div>"
        + (
            f"<p>Not swept (they follow from the swept ones):</p><ul>{derived}</ul>"
            if derived
            else ""
        )  # fmt: skip
        + "<p class='note'>A continuous parameter piles up when more than 10 % of the runs "
        "share one value; a discrete one when one value holds improbably many runs for its "
        "values hit evenly (docs/campaigns.md).</p>"
    )


def _maps(done: Sequence[RunRecord], document: dict[str, Any]) -> str:
    """The pass/fail map of the best pair, the others one click away, and the boundary."""
    parameters = document.get("parameters", {})
    domains = parameters.get("domains", {})
    failures = document.get("failures", {})
    found = failures.get("map", {})
    pair, pairs = found.get("pair"), found.get("pairs", [])
    parts = []
    if pair is None:
        swept = parameters.get("swept", [])
        parts.append(
            "<p>The pass/fail map needs two swept parameters; this campaign swept "
            f"{len(swept)}: the KPIs below show the runs over "
            f"{', '.join(f'<code>{_e(n)}</code>' for n in swept) or 'none'}.</p>"
        )
    else:
        x, y = pair
        score = next(p for p in pairs if [p["x"], p["y"]] == pair)
        parts.append(
            f"<p>Runs over <code>{_e(x)}</code> and <code>{_e(y)}</code>: of the pairs of swept "
            "parameters, the one over which a two-level decision tree separates the runs that "
            f"failed from those that passed with the fewest runs on the wrong side "
            f"({score['wrong']} of {score['runs']}; splits by Gini impurity, each kept when it "
            "puts fewer runs on the wrong side; ties to the cover items, then the order of the "
            "parameters).</p>"
            + _png(pass_fail_map(done, x, y, domains), f"pass/fail map over {x} and {y}")
        )
        for other in pairs:
            if [other["x"], other["y"]] == pair:
                continue
            caption = f"pass/fail map over {other['x']} and {other['y']}"
            parts.append(
                f"<details><summary>{_e(other['x'])} and {_e(other['y'])} ({other['wrong']} "
                f"of {other['runs']} runs on the wrong side)</summary>"
                + _png(pass_fail_map(done, other["x"], other["y"], domains), caption)
                + "</details>"
            )
    limit = failures.get("boundary", {})
    regions = "".join(
        f"<li><b>{_e(r['text'])}</b>"
        + (f"<br><span class='note'>{_e('; '.join(r['brackets']))}</span>" if r["brackets"] else "")
        + "</li>"
        for r in limit.get("regions", [])
    )
    parts.append('<h3 id="boundary">Failure boundary</h3>')
    parts.append(f"<ul>{regions}</ul>" if regions else f"<p>None: {_e(limit.get('why', ''))}.</p>")
    return "".join(parts)


def _triage(document: dict[str, Any]) -> str:
    """One row per group of runs that did not pass (reason and region), with a
    representative run to replay."""
    rows = document.get("failures", {}).get("triage", [])
    if not rows:
        return "<p>Every run passed.</p>"
    cells = []
    for row in rows:
        seeds = " ".join(f'<a href="runs/{s}/run.json">{s}</a>' for s in row["seeds"][:30])
        more = f" (+{len(row['seeds']) - 30})" if len(row["seeds"]) > 30 else ""
        rep = row["representative"]
        cells.append(
            f"<tr><td>{len(row['seeds'])}</td><td>{_e(', '.join(row['statuses']))}</td>"
            f"<td>{_e(row['reason'])}</td><td>{_e(row['region'])}</td><td>{seeds}{more}</td>"
            f'<td><a href="runs/{rep}/run.json">{rep}</a></td>'
            f"<td><code>{_e(row['replay'])}</code></td></tr>"
        )
    return (
        "<div class='scroll'><table><tr><th>runs</th><th>outcome</th><th>reason</th>"
        "<th>region</th><th>seeds</th><th>representative</th><th>replay it</th></tr>"
        + "".join(cells)
        + "</table></div><p class='note'>Runs group by their reason (numbers left out) and the "
        "region of the failure boundary's tree they fall in; the representative is the run "
        "nearest the others over the swept parameters.</p>"
    )


def _kpis_over(done: Sequence[RunRecord], document: dict[str, Any]) -> str:
    parameters = document.get("parameters", {})
    domains = parameters.get("domains", {})
    parts = []
    for name in parameters.get("swept", []):
        fig = kpi_figure(done, name, domains)
        if fig is not None:
            parts.append(_png(fig, f"KPIs over {name}, a point a run coloured by its outcome"))
    return "".join(parts) or "<p>No run has a KPI to plot over the swept parameters.</p>"


_CODE = re.compile(r"`([^`]+)`")  # `name` in a text: code
_AS_CODE = r"<code>\1</code>"
_SECTIONS = (
    ("criterion", "Pass criterion"),
    ("parameters", "Parameters"),
    ("failures", "Where runs fail"),
    ("triage", "Triage"),
    ("coverage", "Coverage"),
    ("kpis", "KPIs"),
    ("worst", "Worst runs"),
    ("runs", "All runs"),
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
    params = document.get("parameters", {}).get("swept", [])
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
    unfinished = len(document.get("not_run", [])) + sum(not r.finished for r in records)
    status_note = (
        "" if document["status"] == "complete"
        else f"<p class='failure'>The campaign was <b>{_e(document['status'])}</b>: "
        f"{unfinished} planned runs did not finish "
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
<nav>{"".join(f'<a href="#{key}">{title}</a>' for key, title in _SECTIONS)}</nav>
<h2 id="criterion">Pass criterion</h2>
<p>A run passes when its outcome is <span class="success">success</span>: the scenario's
behaviour ended, with no collision (unless <code>avoid_collisions(false)</code> allows it), no
actor off the road, no phase over its <code>duration</code>. Crash-test protocols grade a test
with an impact by its impact speed: <code>relative_impact_speed_kph</code> (the closing speed at
the first contact) and <code>speed_reduction_kph</code> (the start speed less the speed at
impact; all of it when there was none) are in every run's KPIs.</p>
<table><tr><th>outcome</th><th>runs</th></tr>{outcome_rows}</table>
<h2 id="parameters">Parameters</h2>{_parameters(document)}
<h2 id="failures">Where runs fail</h2>{_maps(done, document)}
<h2 id="triage">Triage</h2>{_triage(document)}
<h2 id="coverage">Coverage</h2>{_coverage(document)}
<h2 id="kpis">KPIs over the parameters</h2>{_kpis_over(done, document)}
<h3>Distributions</h3>{_histograms(done)}
<table><tr><th>KPI</th><th>unit</th><th>min</th><th>median</th><th>mean</th><th>max</th>
<th>runs</th></tr>{kpi_rows}</table>
<p class="note">KPIs are of the subject: the system under test's actor, else the field named
<code>sut</code> or <code>ego</code>, else the first vehicle (docs/campaigns.md).</p>
<h2 id="worst">Worst runs</h2>{_runs_table(worst, params, folder, replay)}
<h2 id="runs">All runs</h2><details><summary>{len(records)} runs</summary>
{_runs_table(records, params, folder, replay)}</details>
"""
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>osc2run campaign: {_e(document['scenario'])}</title>"
        f"<style>{_CSS}</style></head><body>{body}</body></html>\n"
    )
    return write_atomically(folder / REPORT_FILE, page)
