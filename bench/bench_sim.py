"""Throughput of the simulation world: real-time factor and where the wall time goes.

Usage: ``python bench/bench_sim.py [--seconds 20] [--dt 0.002 0.005]``

For each scene it prints the real-time factor (simulated s / wall s), the
wall time per control tick, and the share of wall time spent inside
``mj_step`` against everything else (actuator layer, read-out, events,
controllers). Scenes:

* ``1 sedan``: one car holding 80 kph with lane keeping;
* ``cut-in``: an ego at 80 kph and a car that cuts in front of it and brakes
  (the shape of the design paper's cut-in scenario);
* ``20 vehicles``: 20 cars (2 HGVs) on a 4-lane road, each with its speed and
  Stanley controllers, every third one changing lanes.

Targets (for later, not asserted): cut-in >= 50x real time on one core,
runner overhead <= 25% of wall time, 20 vehicles >= 5x. Figures only; this
script never fails on a slow machine.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import mujoco

from osc2check.road import Road, get_map
from osc2runner.execution.loop import TickLoop
from osc2runner.sim import (
    ActorSpec,
    VehicleController,
    World,
    hgv,
    sedan,
    versions,
)
from osc2runner.sim import world as world_module


class StepTimer:
    """Wraps ``mujoco.mj_step`` as the world module sees it and sums its wall time."""

    def __init__(self) -> None:
        self.total = 0.0
        self._real = mujoco.mj_step

    def __enter__(self) -> StepTimer:
        real = self._real
        clock = time.perf_counter

        def timed(m, d, nstep=1):  # noqa: ANN001, ANN202 - same signature as mj_step
            t0 = clock()
            real(m, d, nstep=nstep)
            self.total += clock() - t0

        world_module.mujoco.mj_step = timed  # type: ignore[attr-defined]
        return self

    def __exit__(self, *exc: object) -> None:
        world_module.mujoco.mj_step = self._real  # type: ignore[attr-defined]


def scene_single(road: Road, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    w = World(road, [ActorSpec("ego", sedan(), s=100, lane=2, speed=80 / 3.6)], dt_physics=dt)
    c = VehicleController(sedan(), road, w.dt_control)
    c.speed.set_target(80 / 3.6, "smooth")
    c.lateral.keep_lane(2)
    return TickLoop.without_scenario(w, {"ego": c}), lambda loop: None


def scene_cut_in(road: Road, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    actors = [
        ActorSpec("ego", sedan(), s=100, lane=1, speed=80 / 3.6),
        ActorSpec("npc", sedan(), s=130, lane=2, speed=90 / 3.6),
    ]
    w = World(road, actors, dt_physics=dt)
    ego = VehicleController(sedan(), road, w.dt_control)
    ego.speed.set_target(80 / 3.6, "smooth")
    ego.lateral.keep_lane(1)
    npc = VehicleController(sedan(), road, w.dt_control)
    npc.speed.set_target(90 / 3.6, "smooth")
    npc.lateral.keep_lane(2)
    loop = TickLoop.without_scenario(w, {"ego": ego, "npc": npc})

    def script(loop: TickLoop) -> None:
        t = loop.world.tick
        if t == 60:  # 3 s: cut in over 3 s
            npc.lateral.change_lane(loop.world.state("npc"), 1, duration=3.0)
        elif t == 140:  # 7 s: brake
            npc.speed.set_target(50 / 3.6, "smooth")

    return loop, script


def scene_many(road: Road, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    actors = []
    for i in range(20):
        lane = 1 + i % road.lane_count
        params = hgv() if i in (0, 9) else sedan()
        actors.append(
            ActorSpec(f"v{i}", params, s=60 + 25 * (i // road.lane_count), lane=lane, speed=25.0)
        )
    w = World(road, actors, dt_physics=dt)
    controllers = {}
    for spec in actors:
        c = VehicleController(spec.params, road, w.dt_control)  # type: ignore[arg-type]
        c.speed.set_target(25.0, "smooth")
        c.lateral.keep_lane(spec.lane or 1)
        controllers[spec.name] = c
    loop = TickLoop.without_scenario(w, controllers)

    def script(loop: TickLoop) -> None:
        if loop.world.tick == 40:
            for k, spec in enumerate(actors):
                if k % 3 == 0:
                    lane = spec.lane or 1
                    target = lane + 1 if lane < road.lane_count else lane - 1
                    controllers[spec.name].lateral.change_lane(
                        loop.world.state(spec.name), target, duration=4.0
                    )

    return loop, script


SCENES = {"1 sedan": scene_single, "cut-in": scene_cut_in, "20 vehicles": scene_many}


def measure(name: str, dt: float, seconds: float) -> None:
    road = get_map("highway_4lane")
    t0 = time.perf_counter()
    loop, script = SCENES[name](road, dt)
    build = time.perf_counter() - t0
    ticks = round(seconds / loop.world.dt_control)
    with StepTimer() as timer:
        t0 = time.perf_counter()
        for _ in range(ticks):
            script(loop)
            loop.step()
        wall = time.perf_counter() - t0
    inside = timer.total / wall
    print(
        f"{name:12s} dt={dt * 1000:4.1f} ms  RTF {seconds / wall:7.1f}x  "
        f"{wall / ticks * 1e3:6.3f} ms/tick  mj_step {inside:6.1%}  outside {1 - inside:6.1%}  "
        f"(outside {(wall - timer.total) / ticks * 1e6:5.0f} us/tick, build {build * 1e3:.0f} ms)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per scene")
    parser.add_argument("--dt", type=float, nargs="+", default=[0.002, 0.005])
    args = parser.parse_args()
    print("versions:", versions())
    for dt in args.dt:
        for name in SCENES:
            measure(name, dt, args.seconds)


if __name__ == "__main__":
    main()
