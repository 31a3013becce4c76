"""The plots of a run say what the scenario says: tests on the data they draw.

One run (a module fixture): the example AEB drives ``ego`` at 75 kph towards a
target at 20 kph, 40 m ahead bumper to bumper; at 1 s the scenario emits
``slippery`` and sets the road friction to 0.7; the AEB brakes from 1.45 s and
still hits the target at 3 s. Each test reads the figures' artists (lines,
markers, limits, legend boxes), not pixels.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.cli import main
from osc2runner.output.plots import NOISE_FLOORS, braking_phases, run_figures, run_marks
from osc2runner.output.world_plot import MIN_MARGIN
from osc2runner.runner import RunResult

ROOT = Path(__file__).resolve().parents[3]
AEB = f"{ROOT / 'examples' / 'controllers' / 'aeb.py'}:Aeb"
KPH = 3.6

SCENARIO = """\
import osc.standard

scenario plotted:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    target: vehicle with:
        keep(it.vehicle_category == car)
    env: environment
    event slippery
    do serial:
        setup: parallel:
            ego.assign_position() with:
                lane(2, at: start)
                speed(75kph, at: start)
            target.assign_position() with:
                lane(same_as: ego, at: start)
                lateral(distance: 0.3m, at: start)
                position(distance: 40m, ahead_of: ego, at: start)
                speed(20kph, at: start)
        test: parallel:
            serial:
                ego.drive(duration: 1s) with:
                    speed(75kph)
                emit slippery
                env.set_road_friction(value: 0.7)
                ego.drive() with:
                    speed(75kph)
            target.drive() with:
                speed(20kph)
"""


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/output/test_plots")


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("plotted")
    (path / "plotted.osc").write_text(SCENARIO, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def result(folder: Path) -> RunResult:
    return run(folder / "plotted.osc", sut=AEB, out=folder / "out", plot=True)


@pytest.fixture(scope="module")
def figures(result: RunResult) -> dict:
    return run_figures(result)


def _collision(result: RunResult) -> tuple[int, float]:
    (event,) = [e for e in result.events if e.kind == "collision"]
    return event.tick, event.time


def _data_axes(fig) -> list:
    """The time axes under the phase strip."""
    return fig.axes[1:]


def _lines(ax, gid=None) -> list:
    return [line for line in ax.get_lines() if line.get_gid() == gid]


def test_the_run_is_the_one_described(result: RunResult) -> None:
    assert result.outcome.status == "failure" and _collision(result)[1] == pytest.approx(3.0)
    assert set(run_figures(result)) == {
        "speed_throttle.png", "accel_jerk.png", "braking.png", "gap_steering.png", "world.png"
    }  # fmt: skip


def test_the_gap_is_bumper_to_bumper_as_the_scenario_says(result, figures) -> None:
    ax = _data_axes(figures["gap_steering.png"])[0]
    assert "bumper to bumper" in ax.get_ylabel()
    (gap,) = _lines(ax)
    values = np.asarray(gap.get_ydata())
    assert values[0] == pytest.approx(40.0, abs=1e-6)  # position(distance: 40m, ahead_of: ego)
    tick, _ = _collision(result)
    assert 0.0 <= values[tick] <= 0.1  # in contact: no gap left (centre to centre: 4.5 m)


def test_every_axis_spans_at_least_its_noise_floor(result, figures) -> None:
    gap_fig = figures["gap_steering.png"]
    steer = _data_axes(gap_fig)[1]
    assert np.nanmax(np.abs(result.telemetry["ego"]["steer"])) < 1e-6  # a straight road
    low, high = steer.get_ylim()
    assert high - low >= NOISE_FLOORS["steer"] - 1e-12 and low < 0.0 < high
    floors = {"speed (kph)": "speed", "acceleration": "accel", "jerk": "jerk",
              "friction": "friction", "gap": "gap", "steer": "steer"}  # fmt: skip
    for fig in figures.values():
        for ax in fig.axes:
            for label, floor in floors.items():
                if label in ax.get_ylabel():
                    low, high = ax.get_ylim()
                    assert high - low >= NOISE_FLOORS[floor] - 1e-12, ax.get_ylabel()


def test_legends_sit_off_the_data(figures) -> None:
    for name, fig in figures.items():
        fig.canvas.draw()
        for ax in fig.axes:
            legend = ax.get_legend()
            if legend is None:
                continue
            box, area = legend.get_window_extent(), ax.get_window_extent()
            overlap_x = min(box.x1, area.x1) - max(box.x0, area.x0)
            overlap_y = min(box.y1, area.y1) - max(box.y0, area.y0)
            assert overlap_x <= 1.0 or overlap_y <= 1.0, (name, ax.get_ylabel())


def test_collisions_environment_changes_emits_and_the_sut_are_marked(result, figures) -> None:
    _, when = _collision(result)
    marks = run_marks(result)
    assert marks.environment == [(1.0, "set_road_friction 0.7")]
    assert marks.emits == [(1.0, "slippery")]
    assert marks.sut == [(1.45, pytest.approx(3.0))]  # the AEB brakes until the collision
    for name in ("speed_throttle.png", "accel_jerk.png", "gap_steering.png"):
        for ax in _data_axes(figures[name]):
            assert [line.get_xdata()[0] for line in _lines(ax, "collision")] == [when]
            assert [line.get_xdata()[0] for line in _lines(ax, "environment")] == [1.0]
            assert [line.get_xdata()[0] for line in _lines(ax, "emit")] == [1.0]
            (span,) = [p for p in ax.patches if p.get_gid() == "sut"]
            x0, x1 = span.get_x(), span.get_x() + span.get_width()
            assert (x0, x1) == (pytest.approx(1.45), pytest.approx(when))


def test_phase_starts_and_ends_are_bars_of_the_phase_strip(result, figures) -> None:
    strip = figures["speed_throttle.png"].axes[0]
    names = [t.get_text() for t in strip.get_yticklabels()]
    bars = [p for p in strip.patches if p.get_gid() == "phase"]
    spans = {
        (names[round(b.get_y() + b.get_height() / 2)], round(b.get_x(), 6),
         round(b.get_x() + b.get_width(), 6))
        for b in bars
    }  # fmt: skip
    _, end = _collision(result)
    assert ("ego.drive", 0.0, 1.0) in spans  # the first drive ends at its duration
    assert ("ego.drive", 1.0, end) in spans  # the second runs until the collision ends the run
    assert ("test", 0.0, end) in spans and ("target.drive", 0.0, end) in spans
    assert [p.ending for p in run_marks(result).phases if p.name == "ego.drive"] == [
        "end", "running"
    ]  # fmt: skip


def test_friction_is_plotted_over_time(result, figures) -> None:
    ax = _data_axes(figures["accel_jerk.png"])[2]
    assert "friction" in ax.get_ylabel()
    (ego,) = [line for line in _lines(ax) if line.get_label() == "ego"]
    drawn = np.asarray(ego.get_ydata())
    np.testing.assert_array_equal(drawn, result.telemetry["ego"]["friction"])
    assert drawn[0] == pytest.approx(1.0) and drawn[-1] == pytest.approx(0.7)


def test_a_braking_that_ends_in_a_crash_is_plotted(result, figures) -> None:
    tick, _ = _collision(result)
    ego = result.telemetry["ego"]
    (phase,) = braking_phases(ego, [tick])
    assert phase.ending == "collision" and ego["tick"][phase.end] == tick
    ax = figures["braking.png"].axes[0]
    (line,) = _lines(ax, "braking-collision")
    assert np.asarray(line.get_ydata())[-1] == pytest.approx(ego["speed"][phase.end] * KPH)
    assert "collision at" in line.get_label()
    assert _lines(ax, "end-collision")  # the end marked where it hit


def test_world_is_zoomed_to_the_paths_with_collisions_and_time_dots(result, figures) -> None:
    fig = figures["world.png"]
    ax = fig.axes[0]
    fig.canvas.draw()
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    xs = np.concatenate([ch["x"] for ch in result.telemetry.values()])
    ys = np.concatenate([ch["y"] for ch in result.telemetry.values()])
    margin = max(MIN_MARGIN, 0.1 * (xs.max() - xs.min()))
    assert x0 <= xs.min() and xs.max() <= x1 and y0 <= ys.min() and ys.max() <= y1
    assert x1 - x0 <= xs.max() - xs.min() + 2 * margin + 1e-6
    box = ax.get_position()
    assert box.width * box.height >= 0.45  # the view fills the figure, not a line on a page
    tick, _ = _collision(result)
    hits = {(round(float(m.get_xdata()[0]), 6), round(float(m.get_ydata()[0]), 6))
            for m in _lines(ax, "collision")}  # fmt: skip
    expected = {(round(float(ch["x"][tick]), 6), round(float(ch["y"][tick]), 6))
                for ch in result.telemetry.values()}  # fmt: skip
    assert hits == expected
    ego = result.telemetry["ego"]
    dots = [m for m in _lines(ax, "time-dot") if m.get_color() == _lines(ax)[0].get_color()]
    (dot,) = dots
    rows = np.flatnonzero(np.isclose(np.mod(ego["time"] + 1e-9, 0.5), 0.0, atol=1e-6))[1:]
    np.testing.assert_allclose(dot.get_xdata(), ego["x"][rows])


def test_distance_along_the_route_beside_the_road_s(result) -> None:
    """On a straight road the distance travelled is how far the road's s moved, whichever
    way the lane runs; the witness's start s plus it is where the actor is along its way."""
    ego = result.telemetry["ego"]
    assert ego["distance"][0] == 0.0 and np.all(np.diff(ego["distance"]) >= 0.0)
    np.testing.assert_allclose(ego["distance"], np.abs(ego["s"] - ego["s"][0]), atol=1e-6)
    start = next(a for a in result.metadata["witness"]["actors"] if a["name"] == "ego")
    along = start["s_m"] + ego["distance"]
    assert along[-1] - along[0] == pytest.approx(ego["x"][-1] - ego["x"][0], abs=1e-6)


def test_csv_times_are_at_the_ticks_precision(folder: Path) -> None:
    rows = (folder / "out" / "telemetry.csv").read_text().splitlines()
    times = {line.split(",")[2] for line in rows[1:]}
    assert "1.45" in times and all(len(t.split(".")[-1]) <= 2 for t in times)
    events = (folder / "out" / "events.csv").read_text()
    assert "\n29,1.45,sut,intervenes,ego," in events


def test_the_summary_names_the_sut_and_the_impact_speed(folder, result, capsys) -> None:
    status = main([str(folder / "plotted.osc"), "--sut", AEB, "-q"])
    assert status == 1
    out = capsys.readouterr().out
    assert f"system under test: {AEB} driving ego (1 intervention, first at 1.45 s)" in out
    ego = result.telemetry["ego"]["speed"][_collision(result)[0]] * KPH
    assert f"collision at 3.00 s: ego at {ego:.1f} kph, target at 20.0 kph; impact speed" in out
    assert f"{ego - 20.0:.1f} kph" in out


def test_version(capsys) -> None:
    from osc2check.output import tool

    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"osc2run {tool.version()}\n"
