"""Tracking quality: the lateral error of path following and lane changes, per scene.

Usage: ``python bench/bench_tracking.py [--scene NAME ...]``.

Each scene is a scenario run through ``osc2runner`` end to end (the witness, the
behaviour tree, the controllers, the MuJoCo world). For each it prints the largest
lateral error while the action runs:

* a **path** (``follow_path``): the distance of the car's reference point (the
  centre of its bounding box, telemetry ``x``, ``y``) from the path the scenario
  gives, the given points joined as its ``interpolation`` says: a closed-form
  reference, independent of the runner's controller. A corner of a
  ``straight_line`` path cannot be driven exactly by a car: the runner drives it on
  the arc tangent to both lines at the lateral acceleration
  ``osc2runner.sim.tracking.CORNER_ACCEL`` (radius ``R = v^2 / a``), and the scene
  prints how far that arc itself cuts the sharpest corner, ``R (1 - cos(theta / 2))``
  for a corner of angle ``theta``;
* a **lane change** (``change_lane``): the front axle's cross-track error from the
  planned lateral path (telemetry ``lateral_error``) while the change runs, and the
  centre's distance from the target lane's centre when it ends.

Scenes on the shared maps (``../shared/conformance/opendrive``) are skipped when
the folder is absent. Figures only: nothing is asserted here (the tests hold the
bounds, ``tests/osc2runner/sim/test_tracking_quality.py``).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2check.world.carriageways import carriageways, lane_at  # noqa: E402
from osc2check.world.maps import load_map  # noqa: E402
from osc2check.world.projection import lane_centre  # noqa: E402
from osc2runner import run  # noqa: E402
from osc2runner.behaviours.road_paths import road_line  # noqa: E402
from osc2runner.sim.tracking import Polyline  # noqa: E402

SHARED = ROOT.parent / "shared" / "conformance" / "opendrive"
BUNDLED = ROOT / "examples" / "maps"

#: lane 1 to lane 3 of the built-in road with two 10 degree corners (the path test's)
KINKED = [(30.0, 1.75), (70.0, 1.75), (110.0, 8.75), (150.0, 8.75)]


@dataclass(frozen=True)
class Scene:
    name: str
    source: Callable[[], str]  # the scenario text
    measure: Callable[[object], tuple[float, str]]  # run result -> (error m, detail)
    needs: Path | None = None  # a map file that must exist


def _poses(points: list[tuple[float, float]]) -> str:
    lines = []
    for i, (x, y) in enumerate(points):
        lines += [
            f"    p{i}: pose_3d with:",
            f"        keep(it.position.x == {x}m)",
            f"        keep(it.position.y == {y}m)",
        ]
    return "\n".join(lines) + "\n"


def path_scene(points: list[tuple[float, float]], interpolation: str, kph: float) -> str:
    names = ", ".join(f"p{i}" for i in range(len(points)))
    x0, y0 = points[0]
    return (
        "import osc.standard\n\nscenario tracking:\n    car: vehicle\n    m: map\n"
        + _poses(points)
        + f"""\
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: {x0}m, at: start)
            speed({kph}kph, at: start)
        car.follow_path(m.create_path([{names}], {interpolation})) with:
            speed({kph}kph)
"""
    )


def action_rows(result, action: str = "follow_path") -> slice:
    """The telemetry rows while ``car.<action>`` runs, from the row after its start (the
    first row is where the witness put the car, before an ``assign_position``)."""
    start = result.event_ticks("start", f"car.{action}")[0]
    end = result.event_ticks("end", f"car.{action}")[0]
    return slice(start + 1, end + 1)


def line_error(result, line: Polyline) -> float:
    """The car's largest distance from ``line`` while it follows the path."""
    car = result.telemetry["car"]
    rows = action_rows(result)
    return float(line.distances(car["x"][rows], car["y"][rows]).max())


def path_error(points: list[tuple[float, float]], interpolation: str) -> Callable:
    def measure(result) -> tuple[float, str]:
        return line_error(result, Polyline(points, interpolation)), ""

    return measure


def corner_floor(points: list[tuple[float, float]], kph: float, accel: float) -> float:
    """The least error a car at ``kph`` can have at the sharpest corner of the polyline."""
    v = kph / 3.6
    radius = v * v / accel
    worst = 0.0
    for a, b, c in zip(points, points[1:], points[2:], strict=False):
        h1 = math.atan2(b[1] - a[1], b[0] - a[0])
        h2 = math.atan2(c[1] - b[1], c[0] - b[0])
        theta = abs((h2 - h1 + math.pi) % (2 * math.pi) - math.pi)
        worst = max(worst, radius * (1.0 - math.cos(theta / 2.0)))
    return worst


def kinked(kph: float) -> Scene:
    def measure(result) -> tuple[float, str]:
        error, _ = path_error(KINKED, "straight_line")(result)
        try:
            from osc2runner.sim.tracking import CORNER_ACCEL
        except ImportError:  # before corners were rounded
            return error, ""
        return error, f"the arc cuts the corner by {corner_floor(KINKED, kph, CORNER_ACCEL):.3f} m"

    return Scene(
        f"path straight_line {kph:g} kph", lambda: path_scene(KINKED, "straight_line", kph), measure
    )


def smooth(kph: float) -> Scene:
    return Scene(
        f"path smooth {kph:g} kph",
        lambda: path_scene(KINKED, "smooth", kph),
        path_error(KINKED, "smooth"),
    )


def map_scenario(map_file: str) -> str:
    """The scenario's head on ``map_file``, down to its ``do serial:``."""
    return f"""\
import osc.standard

scenario tracking:
    town: map with:
        keep(it.map_file == "{map_file}")
    car: vehicle
    do serial:
"""


def lane_change_scene(map_file: str, lane: int, distance: float, side: str, kph: float) -> str:
    return (
        map_scenario(map_file)
        + f"""\
        car.drive(duration: 2s) with:
            lane({lane}, at: start)
            position(distance: {distance}m, at: start)
            speed({kph}kph)
        car.change_lane(num_of_lanes: 1, side: {side}) with:
            speed({kph}kph)
        car.drive(duration: 2s) with:
            speed({kph}kph)
"""
    )


def lane_change_error(result) -> tuple[float, str]:
    car = result.telemetry["car"]
    start = result.event_ticks("start", "car.change_lane")[0]
    end = result.event_ticks("end", "car.change_lane")[0]
    error = float(np.max(np.abs(car["lateral_error"][start : end + 1])))
    info = result.metadata["map"]
    network = load_map(info["source"] or info["name"])
    row = end + 1  # the state after the change's last tick
    here = network.to_road(float(car["x"][row]), float(car["y"][row]), float(car["yaw"][row]))
    return error, f"centre {abs(here.offset):.3f} m from the lane centre at the end"


def lane_change(
    name: str,
    map_file: str,
    lane: int,
    distance: float,
    side: str,
    kph: float,
    needs: Path | None = None,
) -> Scene:
    return Scene(
        f"lane change {name} {kph:g} kph",
        lambda: lane_change_scene(map_file, lane, distance, side, kph),
        lane_change_error,
        needs,
    )


#: lateral offsets (m, left of the lane centre) of the points of a road path, every 40 m
ROAD_OFFSETS = (0.0, 0.0, 1.2, 1.2, -1.2, -1.2, 0.0, 0.0)
#: a road path into the lane on the left and back (3.5 m lanes)
LANE_TO_LANE = (0.0, 0.0, 3.5, 3.5, 3.5, 0.0, 0.0, 0.0)


def road_points(map_file: str, offsets: tuple[float, ...]) -> list[tuple[str, int, float, float]]:
    """OpenDRIVE points ``(road, lane id, s, t from the lane centre)`` every 40 m along the
    first lane of the map's longest carriageway, straight on through junctions, each
    ``offsets[k]`` left of the lane centre in the direction of travel."""
    network = load_map(map_file)
    cw = max(carriageways(network), key=lambda c: c.length)
    lane = lane_at(network, cw, 5.0, 1)
    route = network.route(lane, ["straight"] * 8, max_length=40.0 * len(offsets) + 60.0)
    points = []
    for k, offset in enumerate(offsets):
        i = int(np.searchsorted(route.path.distance, 5.0 + 40.0 * k))
        x = float(route.path.x[i]) - offset * math.sin(float(route.path.heading[i]))
        y = float(route.path.y[i]) + offset * math.cos(float(route.path.heading[i]))
        here = network.to_road(x, y)
        ref = route.lanes[int(route.path.lane_of[i])]
        centre, _ = lane_centre(network, ref, np.array([here.s]))
        points.append((here.road, ref.lane, here.s, here.t - float(centre[0])))
    return points


def road_path_scene(map_file: str, points, interpolation: str, kph: float) -> str:
    odr = ", ".join(
        f'town.create_odr_point("{road}", "{lane}", {s:.3f}m, {t:.3f}m)'
        for road, lane, s, t in points
    )
    return (
        map_scenario(map_file)
        + f"""\
        car.assign_position(odr_point: town.create_odr_point("{points[0][0]}", "{points[0][1]}", \
{points[0][2]:.3f}m, {points[0][3]:.3f}m)) with:
            speed({kph}kph, at: start)
        car.follow_path(town.create_path_odr_points([{odr}], {interpolation}, true)) with:
            speed({kph}kph)
"""
    )


def road_path_error(map_file: str, points, interpolation: str) -> Callable:
    def measure(result) -> tuple[float, str]:
        network = load_map(map_file)
        xy = []
        for road, lane, s, t in points:
            centre, _ = lane_centre(network, network.lane_at(road, s, lane), np.array([s]))
            pose = network.to_world(road, s, float(centre[0]) + t)
            xy.append((pose.x, pose.y))
        return line_error(result, road_line(network, xy, interpolation)), ""

    return measure


def road_path(
    map_path: Path, interpolation: str, kph: float, offsets=ROAD_OFFSETS, label: str = ""
) -> Scene:
    def points():
        return road_points(str(map_path), offsets)

    return Scene(
        f"road path {map_path.stem} {label}{interpolation} {kph:g} kph",
        lambda: road_path_scene(str(map_path), points(), interpolation, kph),
        lambda result: road_path_error(str(map_path), points(), interpolation)(result),
        map_path,
    )


def scenes(shared: Path = SHARED) -> list[Scene]:
    e6 = shared / "esmini_e6mini.xodr"
    return (
        [
            kinked(30.0),
            kinked(50.0),
            smooth(30.0),
            smooth(50.0),
            lane_change("default", "default", 1, 50.0, "left", 30.0),
            lane_change("default", "default", 1, 50.0, "left", 50.0),
            lane_change("highway_4lane", "highway_4lane", 3, 100.0, "right", 50.0),
            lane_change("esmini_e6mini", str(e6), 3, 200.0, "right", 50.0, e6),
            lane_change("esmini_e6mini", str(e6), 1, 600.0, "left", 50.0, e6),
        ]
        + [
            road_path(path, interpolation, 50.0)
            for path in sorted(BUNDLED.glob("*.xodr")) + sorted(shared.glob("*.xodr"))
            for interpolation in ("straight_line", "smooth")
        ]
        + [
            road_path(path, interpolation, 50.0, LANE_TO_LANE, "lane to lane ")
            for path in (BUNDLED / "rural_curves.xodr", e6)
            for interpolation in ("straight_line", "smooth")
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", nargs="*", help="scene names (a substring) to run")
    parser.add_argument(
        "--shared", type=Path, default=SHARED, help="the shared OpenDRIVE maps' folder"
    )
    args = parser.parse_args()
    chosen = [
        s
        for s in scenes(args.shared)
        if not args.scene or any(word in s.name for word in args.scene)
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for i, scene in enumerate(chosen):
            if scene.needs is not None and not scene.needs.exists():
                print(f"{scene.name:<40} skipped: {scene.needs} is absent")
                continue
            path = Path(tmp) / f"scene{i}.osc"
            path.write_text(scene.source())
            result = run(path)
            if result.outcome.status != "success":
                print(f"{scene.name:<40} {result.outcome.status}: {result.outcome.reason}")
                continue
            error, detail = scene.measure(result)
            print(f"{scene.name:<40} lateral error {error:6.3f} m  {detail}")


if __name__ == "__main__":
    main()
