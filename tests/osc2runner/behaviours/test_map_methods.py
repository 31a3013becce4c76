"""The map methods at run time, against the map's own geometry (the bundled maps).

Route points are on a road driven one way: ``s`` from the route's start in its
direction of travel, ``t`` left of the reference line in that direction.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from osc2check.verify.map_modifiers import ElementValue
from osc2runner.behaviours import maps
from osc2runner.execution.context import RunFault
from osc2runner.runner import prepare

ROOT = Path(__file__).resolve().parents[3]
MAPS = ROOT / "examples" / "maps"

SCENARIO = """\
import osc.standard

scenario s:
    town: map with:
        keep(it.map_file == "{map}")
    car: vehicle
    do car.drive(duration: 2s) with:
        lane(1, at: start)
        position(distance: 50m, at: start)
"""


@pytest.fixture(scope="module")
def rural(tmp_path_factory: pytest.TempPathFactory):  # noqa: ANN201
    source = tmp_path_factory.mktemp("maps") / "s.osc"
    source.write_text(SCENARIO.format(map=MAPS / "rural_curves.xodr"))
    # the start carriageway is drawn by seed: seed 3's is the right lane, along s
    return prepare(source, seed=3).ctx


def test_xyz_and_route_points_round_trip_on_the_road(rural) -> None:  # noqa: ANN001
    network = rural.network
    pose = network.to_world("1", 300.0, -1.75)  # on the 100 m arc, right lane centre
    point = maps.xyz_to_route_point(rural, None, pose.x, pose.y, 0.0)
    assert point.route == ElementValue("route", road="1", direction=1)
    assert (point.s, point.t) == pytest.approx((300.0, -1.75))
    xyz = maps.route_point_to_xyz(rural, None, point)
    assert (xyz.position.x, xyz.position.y) == pytest.approx((pose.x, pose.y), abs=1e-6)
    # the left lane drives against s: its route point counts from the other end
    left = network.to_world("1", 300.0, 1.75)
    back = maps.xyz_to_route_point(rural, None, left.x, left.y, 0.0)
    assert back.route.direction == -1
    assert (back.s, back.t) == pytest.approx((980.0 - 300.0, -1.75))


def test_odr_points_measure_t_from_the_lane_centre_when_a_lane_is_given(rural) -> None:  # noqa: ANN001
    point = maps.create_odr_point(rural, None, "1", "-1", 120.0, 0.5)
    road, s, t = maps.odr_coordinates(rural, point)
    assert (road, s, t) == ("1", 120.0, pytest.approx(-1.75 + 0.5))
    route = maps.odr_to_route_point(rural, None, "1", "", 120.0, 1.0)
    assert route.route.direction == -1 and route.s == pytest.approx(860.0)
    with pytest.raises(RunFault, match="no road `9`"):
        maps.create_odr_point(rural, None, "9", "", 0.0, 0.0)


def test_the_actor_s_route_point_and_distances(rural) -> None:  # noqa: ANN001
    from osc2runner.behaviours.methods import get_s_coord, get_t_coord

    state = rural.states["car"]
    # the car starts 50 m along the right lane (lane -1, along s): its road coordinates
    assert get_s_coord(rural, rural.actors["car"]) == pytest.approx(50.0)
    assert get_t_coord(rural, rural.actors["car"]) == pytest.approx(-1.75)
    here = maps.get_route_point(rural, rural.actors["car"])
    assert (here.s, here.route.road) == (pytest.approx(state.s), "1")
    ahead = maps.create_route_point(rural, None, ElementValue("road", road="1"), state.s + 25, 0.0)
    assert maps.distance_to_route_point(rural, rural.actors["car"], ahead) == pytest.approx(25.0)
    road = ElementValue("route", road="1", direction=1)
    along = maps.distance_along_route(rural, rural.actors["car"], road, "from_start")
    to_end = maps.distance_along_route(rural, rural.actors["car"], road, "from_end")
    assert along == pytest.approx(state.s) and along + to_end == pytest.approx(980.0)
    start, end = maps.start_point(rural, road), maps.end_point(rural, road)
    assert (start.s, end.s) == (0.0, pytest.approx(980.0))


def test_map_facts_and_routes(rural, tmp_path: Path) -> None:  # noqa: ANN001
    assert maps.get_map_file(rural, None) == str((MAPS / "rural_curves.xodr").resolve())
    assert (maps.outer_side(rural, None), maps.inner_side(rural, None)) == ("right", "left")
    source = tmp_path / "j.osc"
    source.write_text(SCENARIO.format(map=MAPS / "four_way_junction.xodr"))
    junction = prepare(source).ctx
    arms = [ElementValue("road", road=r) for r in ("1", "101", "3")]
    assert maps.create_route(junction, None, arms).roads == ("1", "101", "3")
    with pytest.raises(RunFault, match="no lane leads from road `3` to road `101`"):
        maps.create_route(junction, None, [arms[2], arms[1]])
    assert math.isfinite(junction.states["car"].s)
