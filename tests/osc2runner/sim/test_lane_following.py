"""Lane following on real maps against closed-form geometry and the issue's bounds.

A sedan holds 50 kph in one lane of each shared map (``../shared/conformance/
opendrive``, skipped when absent) and of each bundled map for 20 s, through
junctions where its lane leads into one (straight on: a 50 kph turn on a 10 m
radius would leave the road, as it should). Its lateral error stays under
0.3 m everywhere. On the bundled rural road's 100 m left-hand arc the car's
centre stays within 0.1 m of the circle the lane's centre runs on (radius
101.75 m about the arc's centre, computed from the geometry record). A lane
change between lanes of different widths ends on the target lane's centre.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2check.world.elements import map_elements
from osc2check.world.geometry import Cubic, Geometry
from osc2check.world.layout import build_network
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.specs import LaneSpec, NetworkSpec, RoadSpec, SectionSpec
from osc2runner.sim import ActorSpec, VehicleController, World, sedan

ROOT = Path(__file__).resolve().parents[3]
SHARED = ROOT.parent / "shared" / "conformance" / "opendrive"
BUNDLED = ROOT / "examples" / "maps"
V50 = 50.0 / 3.6

#: map -> (start lane, road s of the start): a lane with 20 s of road ahead at 50 kph
STARTS = {
    "esmini_curves.xodr": (LaneRef("1", 0, -1), 5.0),
    "esmini_e6mini.xodr": (LaneRef("0", 0, -3), 5.0),
    "esmini_fabriksgatan.xodr": (LaneRef("2", 0, -1), 5.0),
    "ncap_straight.xodr": (LaneRef("0", 0, 1), 1495.0),
    "ncap_x_intersection.xodr": (LaneRef("0", 0, -1), 5.0),
    "rural_curves.xodr": (LaneRef("1", 0, 1), 975.0),
    "four_way_junction.xodr": (LaneRef("1", 0, -1), 5.0),
}


def _drive(
    network: RoadNetwork, lane: LaneRef, s: float, seconds: float, towards: list[str] = ()
) -> tuple[World, VehicleController, list[tuple[float, ...]]]:
    world = World(network, [ActorSpec("ego", sedan(), s=s, lane=lane, speed=V50)])
    ctrl = VehicleController(sedan(), network, world.dt_control)
    ctrl.lateral.on_route = lambda path: world.follow("ego", path)
    ctrl.lateral.set_route(towards)
    ctrl.speed.set_target(V50, "none")
    ctrl.lateral.keep_lane(lane)
    rows = []
    for _ in range(round(seconds / world.dt_control)):
        world.step_control({"ego": ctrl.step(world.state("ego"))})
        st = world.state("ego")
        rows.append((st.x, st.y, ctrl.lateral.error, st.offset, st.distance, st.s))
    return world, ctrl, rows


def _maps() -> list[Path]:
    found = sorted(BUNDLED.glob("*.xodr"))
    if SHARED.is_dir():
        found += sorted(SHARED.glob("*.xodr"))
    return found


@pytest.mark.parametrize("path", _maps(), ids=lambda p: p.name)
def test_twenty_seconds_in_a_lane_stay_within_0_3_m(path: Path) -> None:
    network = load_map(str(path))
    lane, s = STARTS[path.name]
    straight = [
        t.out_road
        for t in map_elements(network).turns
        if t.in_road == lane.road and t.direction == "straight"
    ]
    world, _, rows = _drive(network, lane, s, 20.0, straight[:1])
    table = np.array(rows)
    assert [e.kind for e in world.events] == []  # never off the drivable road
    assert np.abs(table[:, 2]).max() < 0.3  # the front axle's cross-track error
    assert np.nanmax(np.abs(table[:, 3])) < 0.3  # the centre's offset from its lane centre
    assert table[-1, 4] == pytest.approx(20.0 * V50, rel=0.01)  # 20 s at 50 kph


def test_on_a_100_m_arc_the_car_runs_on_the_lane_circle() -> None:
    network = load_map(str(BUNDLED / "rural_curves.xodr"))
    arc = network.roads["1"].geometries[2]
    assert arc.kind == "arc" and arc.curvature == pytest.approx(0.01)
    # the arc's centre, from its start pose and curvature (closed form)
    cx = arc.x - math.sin(arc.hdg) / arc.curvature
    cy = arc.y + math.cos(arc.hdg) / arc.curvature
    radius = 1.0 / arc.curvature + 1.75  # the right lane's centre, 1.75 m outside
    _, _, rows = _drive(network, LaneRef("1", 0, -1), 100.0, 20.0)
    on_arc = [
        math.hypot(x - cx, y - cy) - radius
        for x, y, *_, s in rows
        if arc.s + 10.0 < s < arc.s + arc.length
    ]
    assert len(on_arc) > 200  # most of the 20 s are on the arc
    assert max(abs(e) for e in on_arc) < 0.1


def _two_widths() -> RoadNetwork:
    """A straight 600 m road with a 3.0 m right lane and a 4.25 m lane beside it."""
    lanes = (
        LaneSpec(id=-1, type="driving", widths=(Cubic(0.0, 4.25),)),
        LaneSpec(id=-2, type="driving", widths=(Cubic(0.0, 3.0),)),
    )
    road = RoadSpec(
        id="7",
        name="two widths",
        length=600.0,
        junction=None,
        geometries=(Geometry("line", 0.0, 0.0, 0.0, 0.0, 600.0),),
        sections=(SectionSpec(0.0, lanes),),
    )
    return build_network(NetworkSpec(name="two widths", roads=(road,)))


def test_a_lane_change_ends_on_the_centre_of_a_wider_lane() -> None:
    network = _two_widths()
    world = World(network, [ActorSpec("ego", sedan(), s=20.0, lane=1, speed=V50)])
    ctrl = VehicleController(sedan(), network, world.dt_control)
    ctrl.lateral.on_route = lambda path: world.follow("ego", path)
    ctrl.speed.set_target(V50, "none")
    ctrl.lateral.keep_lane(1)
    for _ in range(20):
        world.step_control({"ego": ctrl.step(world.state("ego"))})
    start = world.state("ego")
    assert (start.lane, start.lane_id) == (1, -2)
    ctrl.lateral.change_lane(start, 2, duration=4.0)
    for _ in range(160):
        world.step_control({"ego": ctrl.step(world.state("ego"))})
    end = world.state("ego")
    # lane -1's centre is 4.25 / 2 = 2.125 m right of the reference line (y = 0)
    assert (end.lane, end.lane_id) == (2, -1)
    assert end.y == pytest.approx(-2.125, abs=0.1)
    assert abs(end.offset) < 0.1 and ctrl.lateral.done(end)


def test_built_in_road_coordinates_are_the_straight_road_s_and_t() -> None:
    network = builtin_network("default")
    world, _, rows = _drive(network, LaneRef("0", 0, -2), 50.0, 2.0)
    st = world.state("ego")
    assert (st.road, st.lane, st.lane_id) == ("0", 2, -2)
    assert st.s == pytest.approx(st.x) and st.t == pytest.approx(st.y - 10.5)
