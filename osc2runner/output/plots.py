"""PNG plots of a run, of the kinds the design paper shows, that say what the scenario says.

* ``speed_throttle.png``: speed, and throttle and brake, over time;
* ``accel_jerk.png``: acceleration, the 1 s-filtered jerk, and the tire-road
  friction (the mean of each actor's tires) over time;
* ``braking.png``: speed against the distance travelled since each brake onset,
  for every braking phase: one that ends at a standstill, in a collision, when
  the brake is released or when the run ends;
* ``gap_steering.png``: the gap from the run's subject (the system under test's
  actor, else ``sut`` or ``ego``, else the first vehicle) to each other actor,
  bumper to bumper along the subject's heading as the scenario and the witness
  count it (negative: behind; 0 alongside or in contact), and the steering;
* ``world.png``: :mod:`osc2runner.output.world_plot`.

Every time plot has a strip of the scenario's phases on top (a bar from each
phase's start to its end; red when it failed) and marks on its axes: emitted
events (grey dashes), collisions (red), environment changes (blue dash-dots:
rain, road friction, ...) and the spans in which a system under test overrode
the driver model (orange). Legends sit outside the axes, on the right, so they
never hide data; an axis spans at least its quantity's noise floor
(:data:`NOISE_FLOORS`), so a steering of 1e-15 is drawn as the straight line it
is. :func:`run_figures` builds the figures (tests read their data);
:func:`plot_run` writes them, each whole or not at all
(:func:`osc2runner.output.files.atomic_open`). Drawn with matplotlib's Agg
canvas directly: no pyplot state, no display needed.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from osc2check.world.network import RoadNetwork
from osc2runner.options import DT_CONTROL
from osc2runner.output.files import atomic_open
from osc2runner.output.gaps import boxes, subject_actor
from osc2runner.output.stops import BRAKE_ONSET, MOVING, STANDSTILL
from osc2runner.output.telemetry import tick_time
from osc2runner.output.world_plot import world_figure

__all__ = [
    "NOISE_FLOORS",
    "Braking",
    "Marks",
    "Phase",
    "braking_phases",
    "plot_run",
    "run_figures",
    "run_marks",
]

KPH = 3.6
RELEASED = 0.5  # s with the brake off that end a braking phase
#: the smallest span an axis of each quantity shows (its unit as plotted)
NOISE_FLOORS = {
    "speed": 5.0,  # kph
    "accel": 1.0,  # m/s²
    "jerk": 2.0,  # m/s³
    "friction": 0.2,
    "gap": 2.0,  # m
    "steer": 0.1,  # fraction of the full lock
    "braking": 5.0,  # kph
}
PEDALS = (-1.08, 1.08)  # throttle up, brake down: the pedals' whole travel
_LEGEND = {"loc": "upper left", "bbox_to_anchor": (1.005, 1.0), "borderaxespad": 0.0}
_COLOURS = {"emit": "0.55", "collision": "red", "environment": "tab:blue", "sut": "tab:orange"}


@dataclass(frozen=True)
class Phase:
    """One phase of the scenario: an action, a scenario or a labelled member, from its
    start to its end (``ending``: ``end``, ``stop``, ``fail``, or ``running`` at the
    end of the run)."""

    name: str
    start: float
    end: float
    ending: str


@dataclass
class Marks:
    """What the time plots mark, read from the event log (times in s)."""

    emits: list[tuple[float, str]] = field(default_factory=list)
    collisions: list[tuple[float, str]] = field(default_factory=list)
    environment: list[tuple[float, str]] = field(default_factory=list)
    sut: list[tuple[float, float]] = field(default_factory=list)  # intervention spans
    phases: list[Phase] = field(default_factory=list)


def _phase_key(kind: str, name: str) -> str | None:
    """The phase an event starts or ends: a label's ``x.start`` is phase ``x``; the root
    scenario's own ``start``/``end`` spans the run and is left out."""
    if name in ("start", "end", "fail"):
        return None
    suffix = f".{kind}" if kind in ("start", "end", "fail") else ""
    return name[: -len(suffix)] if suffix and name.endswith(suffix) else name


def run_marks(result: Any) -> Marks:
    """The marks of ``result``'s time plots (see the module docstring)."""
    marks = Marks()
    end = max((float(ch["time"][-1]) for ch in result.telemetry.values() if len(ch["time"])),
              default=0.0)  # fmt: skip
    open_phases: dict[str, float] = {}
    intervening: float | None = None
    dt = result.metadata.get("dt_control", DT_CONTROL)
    for e in (replace(e, time=tick_time(e.time, dt)) for e in result.events):
        if e.kind == "emit":
            marks.emits.append((e.time, e.name))
        elif e.kind == "collision":
            marks.collisions.append((e.time, " and ".join(e.actors)))
        elif e.kind == "environment":
            what = f"{e.name} {e.detail}".strip()
            if marks.environment and marks.environment[-1][0] == e.time:  # one mark, one text
                what = f"{marks.environment.pop()[1]}; {what}"
            marks.environment.append((e.time, what))
        elif e.kind == "sut":
            if e.name == "intervenes" and intervening is None:
                intervening = e.time
            elif e.name == "hands back" and intervening is not None:
                marks.sut.append((intervening, e.time))
                intervening = None
        elif e.kind in ("start", "end", "stop", "fail"):
            key = _phase_key(e.kind, e.name)
            if key is None:
                continue
            if e.kind == "start":
                open_phases.setdefault(key, e.time)
            elif key in open_phases:
                marks.phases.append(Phase(key, open_phases.pop(key), e.time, e.kind))
    if intervening is not None:
        marks.sut.append((intervening, end))
    marks.phases.extend(Phase(k, t, end, "running") for k, t in open_phases.items())
    marks.phases.sort(key=lambda p: (p.start, p.end))
    return marks


def _figure(rows: int, phases: list[Phase]) -> tuple[Figure, Any, list[Any]]:
    """A figure of a phase strip on top of ``rows`` time axes sharing its x axis."""
    strip = max(0.7, 0.18 * len(phases) + 0.35)
    fig = Figure(figsize=(11, strip + 3.0 * rows), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(rows + 1, 1, height_ratios=[strip] + [3.0] * rows)
    top = fig.add_subplot(grid[0, 0])
    axes = [fig.add_subplot(grid[i + 1, 0], sharex=top) for i in range(rows)]
    return fig, top, axes


def _phase_strip(ax: Any, phases: list[Phase], end: float, title: str) -> None:
    colours = {"end": "tab:green", "stop": "0.55", "fail": "red", "running": "tab:cyan"}
    for row, p in enumerate(phases):
        width = max(p.end - p.start, end * 0.006)  # an instant one shows as a tick
        ax.barh(row, width, left=p.start, height=0.7, color=colours[p.ending], gid="phase")
    ax.set_yticks(range(len(phases)), [p.name for p in phases], fontsize=7)
    ax.set_ylim(len(phases) - 0.5 if phases else 0.5, -0.5)
    ax.set_xlim(0.0, max(end, 1e-9))
    ax.tick_params(labelbottom=False)
    ax.set_title(title)
    ax.grid(alpha=0.3, axis="x")
    handles = [Patch(color=c, label=f"phase: {k}") for k, c in colours.items()
               if any(p.ending == k for p in phases)]  # fmt: skip
    if handles:
        ax.legend(handles=handles, fontsize=7, **_LEGEND)


def _mark(ax: Any, marks: Marks, labelled: bool) -> list[Any]:
    """Draw ``marks`` on a time axis; the legend handles of the kinds drawn."""
    drawn: dict[str, Any] = {}
    start = ax.get_xlim()[0] + 0.02 * (ax.get_xlim()[1] - ax.get_xlim()[0])
    for t, name in marks.emits:
        ax.axvline(t, color=_COLOURS["emit"], lw=0.8, ls="--", gid="emit")
        if labelled:  # beside its line, inside the axes
            ax.annotate(name, (t, 1.0), xycoords=("data", "axes fraction"), rotation=90,
                        va="top", ha="left" if t < start else "right", fontsize=7,
                        color="0.4")  # fmt: skip
        drawn["emit"] = Line2D([], [], color=_COLOURS["emit"], ls="--", label="emitted event")
    for t, who in marks.collisions:
        ax.axvline(t, color=_COLOURS["collision"], lw=1.6, gid="collision")
        if labelled:
            ax.annotate(f"collision {who}", (t, 0.02), xycoords=("data", "axes fraction"),
                        rotation=90, va="bottom", ha="right", fontsize=7, color="red")  # fmt: skip
        drawn["collision"] = Line2D([], [], color="red", lw=1.6, label="collision")
    for t, what in marks.environment:
        ax.axvline(t, color=_COLOURS["environment"], lw=1.0, ls="-.", gid="environment")
        if labelled:
            ax.annotate(what, (t, 0.5), xycoords=("data", "axes fraction"), rotation=90,
                        va="center", ha="right", fontsize=7, color="tab:blue")  # fmt: skip
        drawn["environment"] = Line2D(
            [], [], color=_COLOURS["environment"], ls="-.", label="environment change"
        )
    for a, b in marks.sut:
        ax.axvspan(a, b, color=_COLOURS["sut"], alpha=0.15, lw=0, gid="sut")
        drawn["sut"] = Patch(color=_COLOURS["sut"], alpha=0.3, label="system under test acts")
    return list(drawn.values())


def _floor(ax: Any, span: float) -> None:
    """Widen the y axis to at least ``span`` around its data (the quantity's noise floor)."""
    values = [np.asarray(line.get_ydata(), dtype=float) for line in ax.get_lines()
              if line.get_gid() is None]  # fmt: skip
    finite = [v[np.isfinite(v)] for v in values]
    finite = [v for v in finite if len(v)]
    if not finite:
        return
    low, high = min(float(v.min()) for v in finite), max(float(v.max()) for v in finite)
    if high - low < span:
        middle = 0.5 * (low + high)
        ax.set_ylim(middle - 0.5 * span, middle + 0.5 * span)


def _finish_axis(ax: Any, extra: list[Any], floor: str | None = None) -> None:
    if floor is not None:
        _floor(ax, NOISE_FLOORS[floor])
    ax.grid(alpha=0.3)
    handles, _ = ax.get_legend_handles_labels()
    if handles or extra:
        ax.legend(handles=handles + extra, fontsize=8, **_LEGEND)


def _moving(result: Any) -> dict[str, dict[str, np.ndarray]]:
    return {
        n: ch
        for n, ch in result.telemetry.items()
        if not np.all(np.isnan(ch["throttle"])) or np.any(ch["speed"] != 0.0)
    }


def _end(result: Any) -> float:
    return max((float(ch["time"][-1]) for ch in result.telemetry.values() if len(ch["time"])),
               default=0.0)  # fmt: skip


def _time_figure(result: Any, marks: Marks, rows: int, title: str) -> tuple[Figure, list[Any]]:
    fig, top, axes = _figure(rows, marks.phases)
    _phase_strip(top, marks.phases, _end(result), title)
    return fig, axes


def _speed_figure(result: Any, actors: dict[str, Any], marks: Marks, title: str) -> Figure:
    fig, (ax1, ax2) = _time_figure(result, marks, 2, title)
    for name, ch in actors.items():
        ax1.plot(ch["time"], ch["speed"] * KPH, label=name)
        if not np.all(np.isnan(ch["throttle"])):
            (line,) = ax2.plot(ch["time"], ch["throttle"], label=f"{name} throttle")
            ax2.plot(ch["time"], -ch["brake"], ls=":", color=line.get_color(),
                     label=f"{name} brake (down)")  # fmt: skip
    ax1.set(ylabel="speed (kph)")
    ax2.set(ylabel="throttle / -brake", xlabel="time (s)", ylim=PEDALS)
    _finish_axis(ax1, _mark(ax1, marks, True), "speed")
    _finish_axis(ax2, _mark(ax2, marks, False))
    return fig


def _accel_figure(result: Any, actors: dict[str, Any], marks: Marks, title: str) -> Figure:
    fig, (ax1, ax2, ax3) = _time_figure(result, marks, 3, f"{title}: acceleration")
    for name, ch in actors.items():
        ax1.plot(ch["time"], ch["accel"], label=name, lw=0.9)
        ax2.plot(ch["time"], ch["jerk"], label=name, lw=0.9)
        if not np.all(np.isnan(ch["friction"])):
            ax3.plot(ch["time"], ch["friction"], label=name, lw=1.2)
    ax1.set(ylabel="acceleration (m/s², 50 ms)")
    ax2.set(ylabel="jerk, 1 s filter (m/s³)")
    ax3.set(ylabel="tire-road friction µ", xlabel="time (s)")
    _finish_axis(ax1, _mark(ax1, marks, True), "accel")
    _finish_axis(ax2, _mark(ax2, marks, False), "jerk")
    _finish_axis(ax3, _mark(ax3, marks, False), "friction")
    return fig


def _gap_figure(
    result: Any, actors: dict[str, Any], marks: Marks, title: str, subject: str
) -> Figure:
    fig, (ax1, ax2) = _time_figure(result, marks, 2, f"{title}: gaps and steering")
    sizes = {
        n: (a["size"]["length"], a["size"]["width"])
        for n, a in result.metadata.get("actors", {}).items()
        if "size" in a
    }
    me = result.telemetry[subject]
    for name, ch in result.telemetry.items():
        if name == subject or name not in sizes:
            continue
        seen = boxes(me, ch, sizes.get(subject, (0.0, 0.0)), sizes[name])
        ax1.plot(me["time"][: len(seen.gap)], seen.signed_gap, label=f"{name} (from {subject})")
    for name, ch in actors.items():
        if not np.all(np.isnan(ch["steer"])):
            ax2.plot(ch["time"], ch["steer"], label=name)
    ax1.set(ylabel="gap, bumper to bumper (m)")
    ax2.set(ylabel="steer (fraction of max)", xlabel="time (s)")
    _finish_axis(ax1, _mark(ax1, marks, True), "gap")
    _finish_axis(ax2, _mark(ax2, marks, False), "steer")
    return fig


@dataclass(frozen=True)
class Braking:
    """One braking phase of an actor: telemetry rows ``start`` (a tick before the brake
    onset) to ``end``, and how it ended: ``stop`` (standstill), ``collision``,
    ``release`` (the brake off for :data:`RELEASED` s) or ``end`` (of the run)."""

    start: int
    end: int
    ending: str


def braking_phases(
    ch: dict[str, np.ndarray], collisions: list[int] | tuple[int, ...] = (), quiet: float = 1.0
) -> list[Braking]:
    """The braking phases of one actor's telemetry ``ch``: from a brake onset (the pedal
    above :data:`~osc2runner.output.stops.BRAKE_ONSET` after being off, while faster than
    :data:`~osc2runner.output.stops.MOVING`; the thresholds of the ``time_to_stop_s``
    KPI) to a standstill, a collision (``collisions``: the ticks of the actor's), a
    release or the end of the run; an onset within ``quiet`` s of the previous phase's
    end belongs to it."""
    brake, speed, time = np.nan_to_num(ch["brake"]), ch["speed"], ch["time"]
    n = len(time)
    hits = sorted(int(np.searchsorted(ch["tick"], t)) for t in collisions)
    found: list[Braking] = []
    last_free = 0.0
    i = 0
    while i < n:
        if not brake[i] > BRAKE_ONSET:
            last_free = time[i]
            i += 1
            continue
        fresh = time[i] - last_free <= 0.2 + 1e-9
        if not fresh or not speed[i] > MOVING or (found and time[i] - time[found[-1].end] < quiet):
            i += 1
            continue
        j, ending, free_since = i, "end", None
        while j < n - 1:
            if speed[j] < STANDSTILL:
                ending = "stop"
                break
            if any(i <= h <= j for h in hits):
                ending = "collision"
                break
            if brake[j] > BRAKE_ONSET:
                free_since = None
            elif free_since is None:
                free_since = time[j]
            elif time[j] - free_since >= RELEASED:
                ending = "release"
                break
            j += 1
        else:
            if speed[j] < STANDSTILL:
                ending = "stop"
            elif any(i <= h <= j for h in hits):
                ending = "collision"
        found.append(Braking(max(i - 1, 0), j, ending))
        i = j + 1
    return found


def _braking_figure(result: Any, actors: dict[str, Any], title: str) -> Figure | None:
    collisions: dict[str, list[int]] = {}
    for e in result.events:
        if e.kind == "collision":
            for actor in e.actors:
                collisions.setdefault(actor, []).append(e.tick)
    phases = [(name, b) for name, ch in actors.items()
              for b in braking_phases(ch, collisions.get(name, []))]  # fmt: skip
    if not phases:
        return None
    fig = Figure(figsize=(11, 4.2 + 0.2 * len(phases)), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    endings = {"stop": "s", "collision": "X", "release": "^", "end": ">"}
    for name, b in phases:
        ch = actors[name]
        x, y = ch["x"][b.start : b.end + 1], ch["y"][b.start : b.end + 1]
        distance = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))))
        speed = ch["speed"][b.start : b.end + 1] * KPH
        mu = ch["friction"][b.start]
        how = {
            "stop": f"stopped after {distance[-1]:.1f} m",
            "collision": f"collision at {speed[-1]:.1f} kph after {distance[-1]:.1f} m",
            "release": f"released at {speed[-1]:.1f} kph after {distance[-1]:.1f} m",
            "end": f"{speed[-1]:.1f} kph when the run ended, after {distance[-1]:.1f} m",
        }[b.ending]
        (line,) = ax.plot(distance, speed, label=f"{name} from {ch['time'][b.start]:.2f} s, "
                          f"µ {mu:.2g}: {how}", gid=f"braking-{b.ending}")  # fmt: skip
        ax.plot(distance[-1:], speed[-1:], endings[b.ending], ms=8, gid=f"end-{b.ending}",
                color="red" if b.ending == "collision" else line.get_color())  # fmt: skip
    ax.set(xlabel="distance from brake onset (m)", ylabel="speed (kph)",
           title=f"{title}: braking")  # fmt: skip
    _floor(ax, NOISE_FLOORS["braking"])
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), borderaxespad=0.0)
    return fig


def run_figures(result: Any, network: RoadNetwork | None = None) -> dict[str, Figure]:
    """The figures of ``result`` by file name (see the module docstring); none when no
    actor moved."""
    actors = _moving(result)
    if not actors:
        return {}
    title = f"{result.metadata['scenario']}: {result.outcome.status}"
    marks = run_marks(result)
    sut = result.metadata.get("sut")
    named = subject_actor(result.metadata.get("actors", {}), sut["actor"] if sut else None)
    subject = named if named is not None and named in result.telemetry else next(iter(actors))
    figures = {
        "speed_throttle.png": _speed_figure(result, actors, marks, title),
        "accel_jerk.png": _accel_figure(result, actors, marks, title),
    }
    braking = _braking_figure(result, actors, title)
    if braking is not None:
        figures["braking.png"] = braking
    if len(result.telemetry) > 1:
        figures["gap_steering.png"] = _gap_figure(result, actors, marks, title, subject)
    figures["world.png"] = world_figure(result, title, network, subject)
    return figures


def plot_run(result: Any, out: Path, network: RoadNetwork | None = None) -> list[Path]:
    """Write the plots of ``result`` into ``out`` (``world.png`` draws the lanes of
    ``network`` when given); returns the files written."""
    out.mkdir(parents=True, exist_ok=True)
    return [_save(fig, out / name) for name, fig in run_figures(result, network).items()]


def _save(fig: Figure, path: Path) -> Path:
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png")
    return path
