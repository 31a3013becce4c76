"""Throughput of the simulation world: real-time factor and where the wall time goes.

Usage: ``python bench/bench_sim.py [--seconds 20] [--dt 0.002 0.005]``

For each scene it prints the real-time factor (simulated s / wall s), the
wall time per control tick, and the share of wall time spent inside
``mj_step`` against everything else (actuator layer, read-out, events,
controllers). Scenes:

* ``1 sedan``: one car holding 80 kph with lane keeping;
* ``1 sedan curved``: one car holding 50 kph in a lane of the bundled
  ``examples/maps/rural_curves.xodr`` (clothoids, a 100 m and a 150 m arc),
  its road coordinates taken on the path it follows, against ``1 sedan
  straight``: the same at 50 kph on the straight built-in road (the
  runner's real-time factor on a curved road should be within 15 % of the
  straight road's);
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
from pathlib import Path

import mujoco

from osc2check.world.builtin import builtin_network
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef, RoadNetwork
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
    """Wraps ``mujoco.mj_step`` as the world module sees it and sums its wall time; also
    sums, over its calls, the contacts, constraint rows and solver iterations of the
    last physics step of each call (what one physics step of the scene costs MuJoCo)."""

    def __init__(self) -> None:
        self.total = 0.0
        self.calls = 0
        self.steps = 0
        self.contacts = 0
        self.rows = 0
        self.iterations = 0
        self._real = mujoco.mj_step

    def __enter__(self) -> StepTimer:
        real = self._real
        clock = time.perf_counter

        def timed(m, d, nstep=1):  # noqa: ANN001, ANN202 - same signature as mj_step
            t0 = clock()
            real(m, d, nstep=nstep)
            self.total += clock() - t0
            self.calls += 1
            self.steps += nstep
            self.contacts += d.ncon
            self.rows += d.nefc
            self.iterations += int(d.solver_niter[0])

        world_module.mujoco.mj_step = timed  # type: ignore[attr-defined]
        return self

    def __exit__(self, *exc: object) -> None:
        world_module.mujoco.mj_step = self._real  # type: ignore[attr-defined]


RURAL = Path(__file__).resolve().parents[1] / "examples" / "maps" / "rural_curves.xodr"


def _controller(world: World, name: str, params, network: RoadNetwork) -> VehicleController:  # noqa: ANN001
    """A driver whose route the world follows for road coordinates (as the runner does)."""
    c = VehicleController(params, network, world.dt_control)
    c.lateral.on_route = lambda path: world.follow(name, path)
    return c


def scene_single(road: RoadNetwork, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    w = World(road, [ActorSpec("ego", sedan(), s=100, lane=2, speed=80 / 3.6)], dt_physics=dt)
    c = _controller(w, "ego", sedan(), road)
    c.speed.set_target(80 / 3.6, "smooth")
    c.lateral.keep_lane(2)
    return TickLoop.without_scenario(w, {"ego": c}), lambda loop: None


def _lane_keeping(
    network: RoadNetwork, lane: LaneRef | int, s: float, dt: float
) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    w = World(network, [ActorSpec("ego", sedan(), s=s, lane=lane, speed=50 / 3.6)], dt_physics=dt)
    c = _controller(w, "ego", sedan(), network)
    c.speed.set_target(50 / 3.6, "none")
    c.lateral.keep_lane(lane)
    return TickLoop.without_scenario(w, {"ego": c}), lambda loop: None


def scene_curved(road: RoadNetwork, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    return _lane_keeping(load_map(str(RURAL)), LaneRef("1", 0, -1), 100.0, dt)


def scene_straight(road: RoadNetwork, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    return _lane_keeping(builtin_network("default"), 2, 100.0, dt)


def scene_cut_in(road: RoadNetwork, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    actors = [
        ActorSpec("ego", sedan(), s=100, lane=1, speed=80 / 3.6),
        ActorSpec("npc", sedan(), s=130, lane=2, speed=90 / 3.6),
    ]
    w = World(road, actors, dt_physics=dt)
    ego = _controller(w, "ego", sedan(), road)
    ego.speed.set_target(80 / 3.6, "smooth")
    ego.lateral.keep_lane(1)
    npc = _controller(w, "npc", sedan(), road)
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


def scene_many(road: RoadNetwork, dt: float) -> tuple[TickLoop, Callable[[TickLoop], None]]:
    actors = []
    lanes = 4
    for i in range(20):
        lane = 1 + i % lanes
        params = hgv() if i in (0, 9) else sedan()
        actors.append(ActorSpec(f"v{i}", params, s=60 + 25 * (i // lanes), lane=lane, speed=25.0))
    w = World(road, actors, dt_physics=dt)
    controllers = {}
    for spec in actors:
        c = _controller(w, spec.name, spec.params, road)
        c.speed.set_target(25.0, "smooth")
        c.lateral.keep_lane(spec.lane or 1)
        controllers[spec.name] = c
    loop = TickLoop.without_scenario(w, controllers)

    def script(loop: TickLoop) -> None:
        if loop.world.tick == 40:
            for k, spec in enumerate(actors):
                if k % 3 == 0:
                    lane = spec.lane if isinstance(spec.lane, int) else 1
                    target = lane + 1 if lane < lanes else lane - 1
                    controllers[spec.name].lateral.change_lane(
                        loop.world.state(spec.name), target, duration=4.0
                    )

    return loop, script


SCENES = {
    "1 sedan": scene_single,
    "1 sedan straight": scene_straight,
    "1 sedan curved": scene_curved,
    "cut-in": scene_cut_in,
    "20 vehicles": scene_many,
}


def measure(name: str, dt: float, seconds: float) -> None:
    road = builtin_network("highway_4lane")
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
        f"{name:16s} dt={dt * 1000:4.1f} ms  RTF {seconds / wall:7.1f}x  "
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
