"""Scenarios through junctions: the Euro NCAP crossing (shared) and the bundled four-way.

A turn across path (Euro NCAP CCFtap): the ego turns left across the path of a
target coming straight through from the opposite road. The checker chooses the
junction and the roads (``map.roads_follow_in_junction``); both cars drive
their connecting roads (telemetry's ``road``), the target clears the crossing
before the ego turns, and the run succeeds.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2check.world.maps import load_map
from osc2runner import run

ROOT = Path(__file__).resolve().parents[3]
NCAP = ROOT.parent / "shared" / "conformance" / "opendrive" / "ncap_x_intersection.xodr"
FOUR_WAY = ROOT / "examples" / "maps" / "four_way_junction.xodr"

TAP = """\
import osc.standard

scenario tap:
    town: map with:
        keep(it.map_file == "{map}")
    ego: vehicle
    target: vehicle
    crossing: junction
    ego_in: road
    ego_out: road
    tgt_in: road
    tgt_out: road
    town.roads_follow_in_junction(junction: crossing, in_road: ego_in, out_road: ego_out,
        direction: left)
    town.roads_follow_in_junction(junction: crossing, in_road: ego_in, out_road: tgt_in,
        direction: straight)
    town.roads_follow_in_junction(junction: crossing, in_road: tgt_in, out_road: tgt_out,
        direction: straight)
    do parallel(duration: 16s):
        ego.drive() with:
            along(route: ego_in, at: start)
            position(distance: {ego_s}m, at: start)
            speed(20kph)
            along(route: ego_out)
        target.drive() with:
            along(route: tgt_in, at: start)
            position(distance: {target_s}m, at: start)
            speed(40kph)
            along(route: tgt_out)
"""


def _turn_across_path(tmp_path: Path, map_path: Path, arm: float, seed: int) -> None:
    source = tmp_path / "tap.osc"
    # the ego 60 m, the target 50 m before the junction at the end of their arms
    source.write_text(TAP.format(map=map_path, ego_s=arm - 60.0, target_s=arm - 50.0))
    result = run(source, seed=seed, out=tmp_path / "out", plot=True)
    assert result.outcome.status == "success", result.outcome.reason
    network = load_map(str(map_path))
    elements = result.metadata["witness"]["map_elements"]
    ego_in, ego_out = elements["ego_in"]["road"], elements["ego_out"]["road"]
    tgt_in, tgt_out = elements["tgt_in"]["road"], elements["tgt_out"]["road"]
    assert tgt_in != ego_in and tgt_out == ego_in  # oncoming, straight through
    for name, first, last in (("ego", ego_in, ego_out), ("target", tgt_in, tgt_out)):
        roads = list(dict.fromkeys(str(r) for r in result.telemetry[name]["road"]))
        inside = [r for r in roads if network.roads[r].junction is not None]
        assert roads[0] == first and roads[-1] == last, (name, roads)
        assert len(inside) == 1, (name, roads)  # one connecting road, the one of its turn
        turn = [
            t
            for t in _turns(network)
            if t.connecting[0] == inside[0] and (t.in_road, t.out_road) == (first, last)
        ]
        assert turn and turn[0].direction == ("left" if name == "ego" else "straight")
        assert np.nanmax(np.abs(result.telemetry[name]["lateral_error"])) < 0.3
    # the target is through the crossing before the ego enters it
    ego_roads = result.telemetry["ego"]["road"]
    tgt_roads = result.telemetry["target"]["road"]
    ego_enters = int(np.argmax(ego_roads != ego_in))
    tgt_leaves = int(np.argmax(tgt_roads == tgt_out))
    assert tgt_leaves < ego_enters
    assert (tmp_path / "out" / "world.png").is_file()


def _turns(network):  # noqa: ANN001, ANN202
    from osc2check.world.elements import map_elements

    return map_elements(network).turns


@pytest.mark.skipif(not NCAP.is_file(), reason="no shared conformance maps")
def test_turn_across_path_at_the_euro_ncap_crossing(tmp_path: Path) -> None:
    _turn_across_path(tmp_path, NCAP, 250.0, seed=0)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_turn_across_path_at_the_bundled_four_way_junction(tmp_path: Path, seed: int) -> None:
    _turn_across_path(tmp_path, FOUR_WAY, 200.0, seed)
