"""RoadLocator: the same road coordinates as the full projection, without its cost each tick."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.opendrive import load_opendrive
from osc2check.world.tracking import OFF_MAP, RoadLocator, RoadPosition

FOUR_WAY = Path(__file__).resolve().parents[3] / "examples" / "maps" / "four_way_junction.xodr"


class _Counting(RoadLocator):
    """A locator that counts its fallbacks to whole-network queries."""

    def __init__(self, network: RoadNetwork) -> None:
        super().__init__(network)
        self.queries = 0
        self.searches = 0

    def _drivable_elsewhere(self, x: float, y: float) -> bool:
        self.queries += 1
        return super()._drivable_elsewhere(x, y)

    def _search(self, x: float, y: float, yaw: float | None) -> RoadPosition:
        self.searches += 1
        return super()._search(x, y, yaw)


class _Asking(RoadLocator):
    """The locator without its per-cell shortcuts: asks the network every time."""

    def _alone(self, x: float, y: float, section: int) -> bool:
        return False

    def _occupied(self, x: float, y: float) -> bool:
        return True


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2check/world/test_tracking")


@pytest.fixture(scope="module")
def crossing() -> RoadNetwork:
    return load_opendrive(FOUR_WAY)


def _same(a: RoadPosition, b: RoadPosition) -> bool:
    fields = ("road", "section", "lane", "direction", "inside", "drivable", "number")
    if any(getattr(a, f) != getattr(b, f) for f in fields):
        return False
    return all(
        (math.isnan(u) and math.isnan(v)) or u == pytest.approx(v, abs=1e-9)
        for u, v in ((a.s, b.s), (a.t, b.t), (a.offset, b.offset))
    )


@pytest.mark.slow
def test_a_walk_over_the_junction_gives_what_asking_the_network_gives(
    crossing: RoadNetwork,
) -> None:
    fast, asking = RoadLocator(crossing), _Asking(crossing)
    drivable = crossing.on_drivable
    for y in np.arange(-30.0, 30.0, 1.3):
        xs = np.arange(-35.0, 35.0, 0.45)
        ys = np.full_like(xs, y)
        expected = drivable(xs, ys)
        for x, wanted in zip(xs.tolist(), expected.tolist(), strict=True):
            got = fast.locate(x, float(y))
            assert _same(got, asking.locate(x, float(y))), (x, y)
            if got.inside:
                assert got.drivable == wanted, (x, y)


@pytest.mark.slow
def test_a_walker_on_a_sidewalk_away_from_the_junction_asks_nothing_of_the_network(
    crossing: RoadNetwork,
) -> None:
    locator = _Counting(crossing)
    sidewalk = LaneRef("1", 0, -2)
    poses = [crossing.lane_to_world(sidewalk, s) for s in np.arange(20.0, 180.0, 0.05)]
    found = [locator.locate(p.x, p.y) for p in poses]
    assert {(f.road, f.lane, f.inside, f.drivable) for f in found} == {("1", -2, True, False)}
    assert locator.queries <= 1
    assert locator.searches == 1  # the first tick only
    # ... but where it meets the junction's roads it still asks
    corner = crossing.lane_to_world(sidewalk, crossing.roads["1"].length - 0.5)
    locator.locate(corner.x, corner.y)
    assert locator.queries >= 1


def test_an_actor_off_every_road_is_off_the_map_without_a_full_search() -> None:
    network = builtin_network("default")
    locator = _Counting(network)
    x0, x1, y0, y1 = network.bounds()
    found = [locator.locate(x, y1 + 50.0) for x in np.linspace(x0, x1, 200).tolist()]
    assert all(f is OFF_MAP for f in found)
    assert locator.searches == 200
    assert network.project(np.array([x0]), np.array([y1 + 50.0])).road[0] == -1
    # the cells it crossed hold no road: no projection was made for them
    calls = 0
    project = network.project

    def counting(*args: object, **kwargs: object) -> object:
        nonlocal calls
        calls += 1
        return project(*args, **kwargs)  # type: ignore[arg-type]

    network.project = counting  # type: ignore[method-assign]
    try:
        assert locator.locate(0.5 * (x0 + x1), y1 + 50.0) is OFF_MAP
    finally:
        del network.project
    assert calls == 0


def test_back_on_the_road_after_leaving_it_the_last_road_is_tried_first() -> None:
    network = builtin_network("default")
    locator = _Counting(network)
    ref = next(iter(network.driving_lanes())).ref
    on = network.lane_to_world(ref, 50.0)
    _, _, _, y1 = network.bounds()
    assert locator.locate(on.x, on.y).inside
    assert locator.locate(on.x, y1 + 50.0) is OFF_MAP
    searches = locator.searches
    back = locator.locate(on.x, on.y)
    assert back.inside and back.road == ref.road
    assert locator.searches == searches
