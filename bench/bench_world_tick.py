"""The world's own cost per control tick, outside the physics: CPU microseconds per tick.

Usage: ``python bench/bench_world_tick.py [--ticks 400] [--root PATH]``

A world of 20 vehicles (2 HGVs), a car towing a caravan, four walkers (two
crossing, two standing) and two obstacles is stepped with fixed inputs, and its
states read out every tick as the runner does (``World.read_states``). The CPU
time (``time.process_time``, less moved than wall time by other work on shared
cores) of each ``mj_step`` call is subtracted, so the figure is what the world
itself adds per tick: actuators, read-out, road positions, events, states.
``--root`` runs another checkout's ``osc2runner`` (e.g. a clone of ``main``) for a
paired comparison (the two commands run in turn, A B A B ...). Figures only; nothing
is asserted.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--ticks", type=int, default=400)
parser.add_argument("--root", default=None, help="the checkout whose osc2runner to run")
args = parser.parse_args()
if args.root:
    sys.path.insert(0, args.root)

import mujoco  # noqa: E402

from osc2check.world.builtin import builtin_network  # noqa: E402
from osc2check.world.catalogue import MODELS  # noqa: E402
from osc2runner.instance.bodies import body_params  # noqa: E402
from osc2runner.sim import (  # noqa: E402
    ActorSpec,
    ObstacleParams,
    PedestrianInput,
    PedestrianParams,
    VehicleInput,
    World,
    hgv,
    sedan,
)


def _row(model: str) -> object:
    row = MODELS[model]
    return body_params(row, float(row.length), float(row.width))


def scene() -> list[ActorSpec]:
    specs = [
        ActorSpec(f"v{i}", hgv() if i % 10 == 0 else sedan(), s=40.0 + 18.0 * (i // 3),
                  lane=1 + i % 3, speed=15.0)
        for i in range(20)
    ]  # fmt: skip
    tow = next(
        p for r in MODELS.values() if getattr(p := body_params(r, float(r.length),
                                                                float(r.width)), "can_tow", False)
    )  # fmt: skip
    specs += [
        ActorSpec("tow", tow, s=5.0, lane=3, speed=10.0),
        ActorSpec("caravan", _row("trailer.caravan"), towed_by="tow"),  # type: ignore[arg-type]
    ]
    specs += [
        ActorSpec(f"w{i}", PedestrianParams(), x=60.0 + 40.0 * i, y=-2.0, yaw=math.pi / 2)
        for i in range(4)
    ]
    specs += [ActorSpec(f"o{i}", ObstacleParams(), s=300.0 + 50 * i, lane=2) for i in range(2)]
    return specs


def main() -> None:
    world = World(builtin_network("default"), scene())
    inputs: dict[str, VehicleInput | PedestrianInput] = {
        f"v{i}": VehicleInput(0.3, 0.0, 0.0) for i in range(20)
    }
    inputs["tow"] = VehicleInput(0.3, 0.0, 0.0)
    inputs["w0"] = inputs["w1"] = PedestrianInput(1.2, math.pi / 2)
    inside = 0.0
    real = mujoco.mj_step

    def timed(m: mujoco.MjModel, d: mujoco.MjData, nstep: int = 1) -> None:
        nonlocal inside
        start = time.process_time()
        real(m, d, nstep=nstep)
        inside += time.process_time() - start

    mujoco.mj_step = timed  # type: ignore[assignment]
    out: dict[str, object] = {}
    start = time.process_time()
    for _ in range(args.ticks):
        world.step_control(inputs)
        world.read_states(out, static=False)  # type: ignore[arg-type]
        world.diverged()
    total = time.process_time() - start
    mujoco.mj_step = real  # type: ignore[assignment]
    outside = total - inside
    print(
        f"{len(world.names)} actors, {args.ticks} ticks: "
        f"{1e3 * total / args.ticks:.3f} ms/tick CPU, "
        f"outside mj_step {1e6 * outside / args.ticks:.0f} us/tick ({100 * outside / total:.1f}%)"
    )


if __name__ == "__main__":
    main()
