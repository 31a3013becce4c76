"""Throughput of the whole runner: real-time factor and the share of wall time outside MuJoCo.

Usage: ``python bench/bench_runner.py [--repeat 2] [--dt 0.002]``, or
``python bench/bench_runner.py --pairs 20`` for the cost of idle pedestrians and
lights: the cut-in and the cut-in+idle scene run in turn (A B A B ...) and each
pair's ratio is taken, so that the load of the shared machine, which drifts
during a measurement, does not decide the figure; the median ratio is printed
(of wall time and of CPU time, the latter less moved by other work).

Scenes, each run through ``osc2runner`` end to end (behaviour tree, controllers,
world, telemetry; the compile and the world's construction are not timed):

* ``cut-in``: the design paper's cut-in scenario
  (``../shared/conformance/seed/cut_in_and_stop.osc`` when present, else
  ``examples/cut_in_and_stop.osc``);
* ``cut-in+idle``: the cut-in with four pedestrians standing far down the road and
  two traffic lights nothing switches (present but idle: target within 5 % of the
  cut-in's real-time factor);
* ``20 vehicles``: a generated scenario: 20 vehicles (2 HGVs) in three
  lanes of a 4-lane road for 30 s; those in the third lane move to the
  fourth after 2 s;
* ``20 kinematic``: the same 20 vehicles, every one moved by the kinematic model,
  the lighter one for background traffic (``--kinematic '*'``; docs/world.md);
* ``cut-in, npc kin.``, ``cut-in, all kin.``: the cut-in with its ``npc``, and with
  both vehicles, on the kinematic model;
* ``straight road`` / ``curved road``: one car 20 s at 50 kph in a lane of the
  built-in straight road, and of ``examples/maps/rural_curves.xodr``
  (clothoids and arcs of 100 m and 150 m radius): the curved road's real-time
  factor should be within 15 % of the straight road's.

For each it prints the real-time factor (simulated s / wall s), the wall time
per control tick and the share spent inside ``mj_step`` against everything
else (tree, controllers, actuator layer, read-out, events, telemetry); then the
same factor from the process's CPU time (less moved by other work on a shared
machine), the physics steps per tick and the wall time of one, and what one
physics step holds (contacts, constraint rows and Newton iterations of the
solver, from the last physics step of each tick). Every vehicle runs the
multibody model (docs/world.md) except in the two scenes that say otherwise.

Targets (not asserted): cut-in >= 100x real time on one core and 20 vehicles
>= 20x (issue 23; before it 50x and 5x; the 20 vehicles by the lighter model for
background traffic, ``20 kinematic``); runner overhead <= 25% of wall time.
Figures only: this script never fails on a slow machine. Other work on shared
cores moves them by ±30%.
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2runner.runner import execute, prepare  # noqa: E402
from osc2runner.sim import versions  # noqa: E402

sys.path.insert(0, str(ROOT / "bench"))
from bench_sim import StepTimer  # noqa: E402  (times mj_step as the world sees it)

SEED_CUT_IN = ROOT.parent / "shared" / "conformance" / "seed" / "cut_in_and_stop.osc"


def many_vehicles(count: int = 20) -> str:
    """``count`` vehicles (two HGVs) in lanes 1-3 of a 4-lane road; lane 3 moves to lane 4."""
    lines = [
        "import osc.standard",
        "",
        "scenario many:",
        "    road_map: map with:",
        '        keep(it.map_file == "highway_4lane")',
    ]
    for i in range(count):
        category = "truck" if i in (0, 9) else "car"
        lines.append(f"    v{i}: vehicle with:")
        lines.append(f"        keep(it.vehicle_category == {category})")
    lines += ["", "    do parallel:"]
    for i in range(count):
        lane = 1 + i % 3
        s = 40 + 35 * (i // 3)
        speed = 60 + 10 * lane
        lines.append("        serial:")
        lines.append(f"            v{i}.assign_position() with:")
        lines.append(f"                lane({lane}, at: start)")
        lines.append(f"                position(distance: {s}m, at: start)")
        lines.append(f"                speed({speed}kph, at: start)")
        if lane == 3:
            lines.append(f"            v{i}.drive(duration: 2s) with:")
            lines.append(f"                speed({speed}kph)")
            lines.append(f"            v{i}.change_lane(num_of_lanes: 1, side: left)")
            lines.append(f"            v{i}.drive(duration: 24s) with:")
        else:
            lines.append(f"            v{i}.drive(duration: 30s) with:")
        lines.append(f"                speed({speed}kph)")
    return "\n".join(lines) + "\n"


def with_idle_vrus_and_lights(source: str, persons: int = 4, lights: int = 2) -> str:
    """The cut-in with ``persons`` pedestrians standing far down the road and ``lights``
    traffic lights that nothing switches: what being present but idle costs."""
    lines = source.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("scenario "))
    first = lines[head + 1]
    unit = " " * (len(first) - len(first.lstrip()))

    def at(level: int, text: str) -> str:
        return unit * level + text

    fields = [at(1, f"p{i}: person") for i in range(persons)]
    for i in range(lights):
        fields += [
            at(1, f"tl{i}: traffic_light with:"),
            at(2, f"keep(it.pose.position.x == {900 + 20 * i}m)"),
            at(2, "keep(it.pose.position.y == -1m)"),
        ]
    lines[head + 1 : head + 1] = fields
    do = next(i for i, line in enumerate(lines) if line.strip() == "do parallel:")
    members = []
    for i in range(persons):
        members += [
            at(2, "serial:"),
            at(3, f"p{i}.assign_position() with:"),
            at(4, f"lane({1 + i % 2}, at: start)"),
            at(4, f"position(distance: {880 + 5 * i}m, at: start)"),
            at(4, "speed(0kph, at: start)"),
        ]
    lines[do + 1 : do + 1] = members
    return "\n".join(lines) + "\n"


def lane_keeping(map_file: str) -> str:
    """One car in a lane for 20 s at 50 kph on ``map_file`` (the curved-road comparison)."""
    return (
        "import osc.standard\n\nscenario keeping:\n"
        f'    town: map with:\n        keep(it.map_file == "{map_file}")\n'
        "    car: vehicle\n"
        "    do car.drive(duration: 20s) with:\n"
        "        lane(1, at: start)\n"
        "        position(distance: 100m, at: start)\n"
        "        speed(50kph)\n"
    )


def measure(name: str, path: Path, dt: float, repeat: int, kinematic: tuple[str, ...] = ()) -> None:
    best = None
    for _ in range(repeat):
        prepared = prepare(path, dt_physics=dt, kinematic=kinematic)
        gc.collect()
        with StepTimer() as timer:
            cpu = time.process_time()
            result = execute(prepared, duration=120.0)
            cpu = time.process_time() - cpu
        wall = result.metadata["wall_seconds"]  # the tick loop (not writing the results)
        if best is None or wall < best[0]:
            best = (wall, cpu, timer, result)
    assert best is not None
    wall, cpu, timer, result = best
    sim = result.metadata["simulated_time"]
    ticks = result.metadata["steps"]
    inside = timer.total
    outside = wall - inside
    calls = max(timer.calls, 1)
    per_step = 1e6 * inside / max(timer.steps, 1)
    print(
        f"{name:<16} dt={dt * 1e3:4.1f} ms  {result.outcome.status:<8} sim {sim:6.2f} s  "
        f"RTF {sim / wall:7.1f}x  {1e3 * wall / max(ticks, 1):6.3f} ms/tick  "
        f"mj_step {100 * inside / wall:5.1f}%  outside {100 * outside / wall:5.1f}%  "
        f"(outside {1e6 * outside / max(ticks, 1):5.0f} us/tick)\n"
        f"{'':<16} CPU RTF {sim / cpu:7.1f}x  {1e3 * cpu / max(ticks, 1):6.3f} ms/tick CPU; "
        f"{timer.steps / calls:.0f} physics steps/tick of {per_step:5.1f} "
        f"us; per step {timer.contacts / calls:.0f} contacts, {timer.rows / calls:.0f} "
        f"constraint rows, {timer.iterations / calls:.2f} solver iterations"
    )


def idle_pairs(cut_in: Path, idle: Path, pairs: int, dt: float) -> None:
    """Interleaved A/B: the cut-in alone and with idle walkers and lights, ``pairs`` times;
    the median of each pair's ratio of tick-loop times (wall and CPU)."""
    wall_ratio, cpu_ratio, extra = [], [], []
    for _ in range(pairs):
        measured = []
        for path in (cut_in, idle):
            prepared = prepare(path, dt_physics=dt)
            gc.collect()
            cpu = time.process_time()
            result = execute(prepared, duration=120.0)
            cpu = time.process_time() - cpu
            measured.append((result.metadata["wall_seconds"], cpu, result.metadata["steps"]))
        (wall_a, cpu_a, ticks_a), (wall_b, cpu_b, ticks_b) = measured
        wall_ratio.append((wall_b / ticks_b) / (wall_a / ticks_a))
        cpu_ratio.append((cpu_b / ticks_b) / (cpu_a / ticks_a))
        extra.append(1e6 * (cpu_b / ticks_b - cpu_a / ticks_a))
    med = statistics.median
    print(
        f"cut-in+idle / cut-in, {pairs} interleaved pairs, dt={dt * 1e3:.1f} ms: time per tick "
        f"x{med(wall_ratio):.3f} wall (range {min(wall_ratio):.3f}-{max(wall_ratio):.3f}), "
        f"x{med(cpu_ratio):.3f} CPU (range {min(cpu_ratio):.3f}-{max(cpu_ratio):.3f}); "
        f"real-time factor {100 * (1 - 1 / med(cpu_ratio)):.1f}% lower (CPU), "
        f"{med(extra):+.1f} us/tick"
    )


#: each scene: its file (see ``main``) and the vehicles it moves by the kinematic model
SCENES: dict[str, tuple[str, tuple[str, ...]]] = {
    "cut-in": ("cut-in", ()),
    "cut-in+idle": ("idle", ()),
    "20 vehicles": ("many", ()),
    "20 kinematic": ("many", ("*",)),
    "cut-in, npc kin.": ("cut-in", ("npc",)),
    "cut-in, all kin.": ("cut-in", ("*",)),
    "straight road": ("straight", ()),
    "curved road": ("curved", ()),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2, help="runs per scene (best is shown)")
    parser.add_argument("--dt", type=float, nargs="+", default=[0.002], help="physics steps")
    parser.add_argument(
        "--scene",
        nargs="+",
        default=list(SCENES),
        help=f"scenes to run ({', '.join(SCENES)})",
    )
    parser.add_argument(
        "--pairs", type=int, default=0, help="interleaved cut-in / cut-in+idle pairs instead"
    )
    args = parser.parse_args()
    print(f"versions: {versions()}")
    cut_in = SEED_CUT_IN if SEED_CUT_IN.exists() else ROOT / "examples" / "cut_in_and_stop.osc"
    with tempfile.TemporaryDirectory() as tmp:
        many = Path(tmp) / "many.osc"
        many.write_text(many_vehicles(), encoding="utf-8")
        idle = Path(tmp) / "cut_in_idle.osc"
        idle.write_text(with_idle_vrus_and_lights(cut_in.read_text()), encoding="utf-8")
        straight = Path(tmp) / "straight.osc"
        straight.write_text(lane_keeping("default"), encoding="utf-8")
        curved = Path(tmp) / "curved.osc"
        rural = ROOT / "examples" / "maps" / "rural_curves.xodr"
        curved.write_text(lane_keeping(str(rural)), encoding="utf-8")
        files = {"cut-in": cut_in, "idle": idle, "many": many, "straight": straight}
        files["curved"] = curved
        if args.pairs:
            for dt in args.dt:
                idle_pairs(cut_in, idle, args.pairs, dt)
            return
        for dt in args.dt:
            for name in args.scene:
                which, kinematic = SCENES[name]
                measure(name, files[which], dt, args.repeat, kinematic)


if __name__ == "__main__":
    main()
