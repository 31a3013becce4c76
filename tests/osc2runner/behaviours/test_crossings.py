"""Crossings from OpenDRIVE objects (issue 20, item 5; ASAM OpenSCENARIO DSL 2.1
``crossing``, ``map.crossing_connects``; OpenDRIVE 1.8 §13 ``<object type="crosswalk">``).

The map: a straight 200 m road along x, one 3.5 m lane each way and a 2 m sidewalk on
each side (sidewalks 3.5 m to 5.5 m from the reference line), and a crosswalk at s 100 m
across the road (``hdg`` 90°), 10 m long and 4 m wide: from (100, -5) in the right
sidewalk to (100, 5) in the left one.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify.api import solve
from osc2check.verify.witness import Witness
from osc2check.world.crossings import crossing_angle, crossing_lanes, crossing_points
from osc2check.world.maps import load_map
from osc2runner import run


def _width(a: float) -> str:
    return f'<width sOffset="0" a="{a}" b="0" c="0" d="0"/>'


XODR = f"""<?xml version="1.0" encoding="utf-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="8" name="crosswalk"/>
  <road id="1" length="200" junction="-1">
    <planView><geometry s="0" x="0" y="0" hdg="0" length="200"><line/></geometry></planView>
    <lanes>
      <laneSection s="0">
        <left>
          <lane id="2" type="sidewalk">{_width(2.0)}</lane>
          <lane id="1" type="driving">{_width(3.5)}</lane>
        </left>
        <center><lane id="0" type="none"/></center>
        <right>
          <lane id="-1" type="driving">{_width(3.5)}</lane>
          <lane id="-2" type="sidewalk">{_width(2.0)}</lane>
        </right>
      </laneSection>
    </lanes>
    <objects>
      <object type="crosswalk" id="zebra" s="100" t="0" zOffset="0" hdg="1.5707963267948966"
              length="10" width="4" orientation="none"/>
      <object type="pole" id="p1" s="20" t="6" zOffset="0" orientation="none"/>
    </objects>
  </road>
</OpenDRIVE>
"""


@pytest.fixture
def crosswalk(tmp_path: Path) -> Path:
    path = tmp_path / "crosswalk.xodr"
    path.write_text(XODR)
    return path


def _scenario(map_file: Path, modifier: str = "", start: str = "") -> str:
    return f"""\
import osc.standard

scenario s:
    town: map with:
        keep(it.map_file == "{map_file.as_posix()}")
    zebra: crossing
    ped: person
    town.crossing_connects(crossing: zebra{modifier})
    do ped.walk() with:
        along(zebra)
        lane(1, at: start)
        lateral(distance: -3m, at: start)
{start}        speed(5kph)
"""


def test_a_crosswalk_object_is_a_crossing_from_sidewalk_to_sidewalk(crosswalk):
    network = load_map(str(crosswalk))
    assert [c.id for c in network.crossings] == ["zebra"]  # the pole is no crossing
    zebra = network.crossings[0]
    start, end = crossing_points(network, zebra)
    assert start == pytest.approx((100.0, -5.0)) and end == pytest.approx((100.0, 5.0))
    assert [ref.lane for ref in crossing_lanes(network, zebra)] == [-2, 2]
    assert crossing_angle(zebra) == pytest.approx(math.pi / 2)


def _check(text: str):
    analysis = analyze([SourceInput("s.osc", text)])
    return analysis, [d for d in analysis.diagnostics if d.severity.name in ("ERROR", "WARNING")]


def test_the_checker_places_a_person_along_a_crossing_where_the_crossing_is(crosswalk):
    analysis, findings = _check(_scenario(crosswalk))
    assert not findings, [d.message for d in findings]
    witness = solve(analysis, seed=0)
    assert isinstance(witness, Witness)
    assert witness.element("zebra") is not None
    assert witness.element("zebra").crossing == "zebra"
    ped = witness.actor("ped")
    assert ped is not None and abs(ped.road_s - 100.0) <= 2.0  # within its 4 m width


@pytest.mark.parametrize(
    ("modifier", "start", "code"),
    [
        (", start_angle: 45deg", "", "C401"),
        ("", "        position(distance: 50m, at: start)\n", "L501"),
    ],
    ids=["no crossing at that angle", "a start away from every crossing"],
)
def test_a_crossing_the_map_does_not_have_is_a_conflict(crosswalk, modifier, start, code):
    _, findings = _check(_scenario(crosswalk, modifier, start))
    assert [d.code.code for d in findings] == [code], [d.message for d in findings]


def test_a_person_walks_across_from_the_kerb_it_stands_at(crosswalk, tmp_path):
    source = tmp_path / "s.osc"
    source.write_text(_scenario(crosswalk))
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    ped = result.telemetry["ped"]
    lanes = [int(x) for x in ped["lane_id"]]
    assert lanes[0] == 2 and lanes[-1] == -2  # one sidewalk to the other
    assert set(lanes) == {2, 1, -1, -2}  # across both driving lanes
    # to the crossing's near end on its sidewalk first, then straight across
    across = np.abs(np.asarray(ped["y"])) < 3.5
    assert np.abs(np.asarray(ped["x"])[across] - 100.0).max() < 0.1
    # it ends at the far end (the path's end, reached at its speed: 5 kph)
    assert ped["y"][-1] == pytest.approx(-5.0, abs=0.2)
