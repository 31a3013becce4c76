"""Road networks: load time, projection speed and memory.

For every shared OpenDRIVE conformance map (``../shared/conformance/opendrive``,
skipped when absent), the bundled maps (``examples/maps``) and the built-in
Town06: the median time to read and lay out the map, the time to build the
projection grid, the memory the loaded network holds (its numpy arrays, and the
peak traced while loading), and world → road projections per second for 100,000
random points near the roads (a road picked in proportion to its length, ``s``
uniform, ``t`` uniform from 2 m right of the right edge to 2 m left of the left
edge), projected in one vectorised call. Target (issue 12): >= 50,000 per second.
"""

from __future__ import annotations

import statistics
import sys
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2check.world.builtin import builtin_map, straight_network  # noqa: E402
from osc2check.world.network import RoadNetwork  # noqa: E402
from osc2check.world.opendrive import load_opendrive  # noqa: E402

SHARED = ROOT.parent / "shared" / "conformance" / "opendrive"
POINTS = 100_000


def median_time(fn: Callable[[], object], repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def near_road_points(net: RoadNetwork, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    lengths = np.array([net.roads[r].length for r in net.road_ids])
    roads = rng.choice(len(lengths), size=n, p=lengths / lengths.sum())
    s = rng.uniform(0.0, 1.0, n) * lengths[roads]
    t = np.empty(n)
    for number, road_id in enumerate(net.road_ids):
        road = net.roads[road_id]
        mask = roads == number
        right = np.interp(s[mask], road.s, np.concatenate([x.borders[-1] for x in road.sections]))
        left = np.interp(s[mask], road.s, np.concatenate([x.borders[0] for x in road.sections]))
        t[mask] = rng.uniform(right - 2.0, left + 2.0)
    x, y, _ = net.road_to_world(roads, s, t)
    return x, y


def array_bytes(net: RoadNetwork) -> int:
    total = 0
    for road in net.roads.values():
        total += sum(a.nbytes for a in (road.s, road.x, road.y, road.heading, road.curvature))
        total += road.offset.nbytes + sum(sec.borders.nbytes for sec in road.sections)
    return total


def index_bytes(net: RoadNetwork) -> int:
    index = net.spatial_index()
    return sum(
        getattr(index, name).nbytes
        for name in index.__dataclass_fields__
        if hasattr(getattr(index, name), "nbytes")
    )


def report(name: str, load: Callable[[], RoadNetwork]) -> None:
    load_time = median_time(load)
    tracemalloc.start()
    net = load()
    net.spatial_index()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    index_time = median_time(lambda: load().spatial_index())
    x, y = near_road_points(net, POINTS)
    net.project(x[:1000], y[:1000])  # warm up
    project_time = median_time(lambda: net.project(x, y))
    on_road = float(np.mean(net.project(x, y).inside))
    road_arrays = array_bytes(net) / 2**20
    grid = index_bytes(net) / 2**20
    print(
        f"{name:28s} roads {len(net.roads):3d}  load {load_time * 1000:6.1f} ms  "
        f"load+index {index_time * 1000:6.1f} ms  "
        f"project {POINTS / project_time / 1000:7.0f} k/s ({on_road:.0%} inside)  "
        f"memory: roads {road_arrays:5.2f} MiB, grid {grid:5.2f} MiB, peak {peak / 2**20:5.1f} MiB"
    )


def main() -> None:
    maps: list[tuple[str, Callable[[], RoadNetwork]]] = []
    if SHARED.is_dir():
        for path in sorted(SHARED.glob("*.xodr")):
            maps.append((path.name, lambda path=path: load_opendrive(path)))
    else:
        print(f"({SHARED} absent: shared maps skipped)")
    for path in sorted((ROOT / "examples" / "maps").glob("*.xodr")):
        maps.append((path.name, lambda path=path: load_opendrive(path)))
    # built fresh each time (builtin_network shares one network per name)
    maps.append(("built-in Town06", lambda: straight_network(builtin_map("Town06"))))
    for name, load in maps:
        report(name, load)


if __name__ == "__main__":
    main()
