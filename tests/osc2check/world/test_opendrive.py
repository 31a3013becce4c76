"""Reading OpenDRIVE: lanes, widths, offsets, directions, signals, and broken files."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.errors import MapError
from osc2check.world.network import LaneRef
from osc2check.world.opendrive import load_opendrive
from tests.osc2check.world.maptext import LANES_2, WIDTH, road_xml, xodr

WriteMap = Callable[..., Path]


def test_lane_widths_are_cubic_in_ds_with_several_records(write_map: WriteMap) -> None:
    lanes = """
      <laneSection s="0">
        <center><lane id="0" type="none"/></center>
        <right>
          <lane id="-1" type="driving">
            <width sOffset="0" a="3.0" b="0.02" c="0" d="0"/>
            <width sOffset="50" a="4.0" b="0" c="-0.001" d="0.00001"/>
          </lane>
          <lane id="-2" type="shoulder"><width sOffset="0" a="1.0" b="0" c="0" d="0"/></lane>
        </right>
      </laneSection>
      <laneSection s="80">
        <center><lane id="0" type="none"/></center>
        <right><lane id="-1" type="driving">
          <width sOffset="5" a="2.5" b="0" c="0.001" d="0"/>
        </lane></right>
      </laneSection>"""
    net = load_opendrive(write_map(xodr(road_xml(lanes=lanes))))
    ref = LaneRef("1", 0, -1)
    s = np.array([0.0, 25.0, 50.0, 60.0, 79.0])
    ds2 = np.clip(s - 50.0, 0, None)
    expected = np.where(s < 50, 3.0 + 0.02 * s, 4.0 - 0.001 * ds2**2 + 0.00001 * ds2**3)
    assert np.allclose(net.width(ref, s), expected, atol=1e-12)
    # The second section: no record before sOffset 5 means width 0 there, then the cubic.
    later = LaneRef("1", 1, -1)
    assert np.allclose(net.width(later, np.array([90.0])), 2.5 + 0.001 * 25)
    # Lane centres: half the width right of the reference line, plus the full inner lane.
    assert net.lane_to_world(ref, 60.0).y == pytest.approx(-0.5 * expected[3], abs=1e-9)
    shoulder = net.lane_to_world(LaneRef("1", 0, -2), 60.0)
    assert shoulder.y == pytest.approx(-(expected[3] + 0.5), abs=1e-9)
    assert net.roads["1"].section_at(85.0).index == 1


def test_lane_widths_from_border_records_on_both_sides(write_map: WriteMap) -> None:
    # <border> gives the outer border's distance from the centre lane; a lane's width
    # is the gap to the border inside it (the centre lane's, at the lane offset, for
    # the lanes next to it), also beside a lane with width records.
    lanes = """
      <laneSection s="0">
        <left>
          <lane id="2" type="shoulder"><border sOffset="0" a="7.0" b="0" c="0" d="0"/></lane>
          <lane id="1" type="driving"><border sOffset="0" a="3.0" b="0.01" c="0" d="0"/></lane>
        </left>
        <center><lane id="0" type="none"/></center>
        <right>
          <lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
          <lane id="-2" type="shoulder"><border sOffset="0" a="5.0" b="0" c="0" d="0"/></lane>
        </right>
      </laneSection>"""
    offset = '\n      <laneOffset s="0" a="0.5" b="0" c="0" d="0"/>'
    net = load_opendrive(write_map(xodr(road_xml(lanes=lanes, lanes_extra=offset))))
    s = np.array([0.0, 40.0, 100.0])
    assert np.allclose(net.width(LaneRef("1", 0, 1), s), 3.0 + 0.01 * s, atol=1e-9)
    assert np.allclose(net.width(LaneRef("1", 0, 2), s), 4.0 - 0.01 * s, atol=1e-9)
    assert np.allclose(net.width(LaneRef("1", 0, -1), s), 3.5, atol=1e-12)
    assert np.allclose(net.width(LaneRef("1", 0, -2), s), 1.5, atol=1e-9)
    centre = net.lane_to_world(LaneRef("1", 0, 2), 40.0)
    assert centre.y == pytest.approx(0.5 + 0.5 * (3.4 + 7.0), abs=1e-9)


def test_lane_offset_shifts_the_centre_lane(write_map: WriteMap) -> None:
    offset = '\n      <laneOffset s="0" a="1.0" b="0.01" c="0" d="0"/>'
    net = load_opendrive(write_map(xodr(road_xml(lanes_extra=offset))))
    for s in (0.0, 40.0, 90.0):
        t0 = 1.0 + 0.01 * s
        left = net.lane_to_world(LaneRef("1", 0, 1), s)
        right = net.lane_to_world(LaneRef("1", 0, -1), s)
        assert left.y == pytest.approx(t0 + 1.75, abs=1e-6)
        assert right.y == pytest.approx(t0 - 1.75, abs=1e-6)
    # The lane centre leans with the offset: its heading is atan(0.01) off the road's.
    assert net.lane_to_world(LaneRef("1", 0, -1), 50.0).yaw == pytest.approx(math.atan(0.01))
    point = net.to_road(50.0, 1.5 + 0.2)
    assert point is not None and point.lane == LaneRef("1", 0, 1)


def test_rht_right_lanes_drive_along_s_and_lht_flips(write_map: WriteMap) -> None:
    rht = load_opendrive(write_map(xodr(road_xml()), "rht.xodr"))
    lht = load_opendrive(write_map(xodr(road_xml(attrs='rule="LHT"')), "lht.xodr"))
    assert rht.lane(LaneRef("1", 0, -1)).direction == 1
    assert rht.lane(LaneRef("1", 0, 1)).direction == -1
    assert lht.lane(LaneRef("1", 0, -1)).direction == -1
    assert lht.lane(LaneRef("1", 0, 1)).direction == 1
    # Heading of travel and left/right follow the direction.
    assert lht.lane_to_world(LaneRef("1", 0, 1), 10.0).yaw == pytest.approx(0.0)
    assert abs(lht.lane_to_world(LaneRef("1", 0, -1), 10.0).yaw) == pytest.approx(math.pi)
    # Under LHT, the lane left of lane 1 (driving +x) is lane 2 side... here none; its
    # right neighbour is the oncoming lane -1.
    n = lht.neighbours(LaneRef("1", 0, 1))
    assert n.left is None and n.right == LaneRef("1", 0, -1) and not n.right_same_direction
    path = lht.lane_path(LaneRef("1", 0, -1))
    assert path.x[0] == pytest.approx(100.0) and path.x[-1] == pytest.approx(0.0)


def test_lane_direction_attribute_reverses_a_lane(write_map: WriteMap) -> None:
    lanes = LANES_2.replace(
        '<lane id="-1" type="driving">', '<lane id="-1" type="driving" direction="reversed">'
    )
    net = load_opendrive(write_map(xodr(road_xml(lanes=lanes))))
    assert net.lane(LaneRef("1", 0, -1)).direction == -1


def test_signals_and_references_are_kept(write_map: WriteMap) -> None:
    signals = """<signals>
      <signal id="7" s="95" t="-4" name="light" dynamic="yes" orientation="+" type="1000001"
              subtype="-1" country="DE" zOffset="2" height="0.9" hOffset="0.1">
        <validity fromLane="-1" toLane="-1"/>
      </signal>
      <signal id="8" s="20" t="4" dynamic="no" orientation="-" type="274" subtype="56"
              value="50" unit="km/h"/>
      <signalReference id="7" s="90" t="3" orientation="-"/>
    </signals>"""
    road = road_xml().replace("    </lanes>\n  </road>", f"    </lanes>\n    {signals}\n  </road>")
    tail = '<controller id="c1" name="group"><control signalId="7" type="0"/></controller>'
    net = load_opendrive(write_map(xodr(road, tail=tail)))
    light, sign = net.signals
    assert (light.id, light.dynamic, light.type, light.country, light.validity) == (
        "7",
        True,
        "1000001",
        "DE",
        ((-1, -1),),
    )
    assert (sign.value, sign.unit, sign.orientation, sign.dynamic) == (50.0, "km/h", "-", False)
    assert net.signal_references[0].s == 90.0
    assert net.controllers[0].signals == ("7",)
    pose = net.signal_pose(light)
    assert (pose.x, pose.y) == pytest.approx((95.0, -4.0))
    assert net.summary().traffic_lights == 1


def test_road_speed_limit_in_units(write_map: WriteMap) -> None:
    extra = '<type s="0" type="rural"><speed max="50" unit="km/h"/></type>'
    net = load_opendrive(write_map(xodr(road_xml(extra=extra))))
    assert net.roads["1"].speed_limit == pytest.approx(50 / 3.6)


# ---------------------------------------------------------------- malformed files

GOOD = xodr(road_xml())


def _case(old: str, new: str) -> str:
    assert old in GOOD
    return GOOD.replace(old, new, 1)


def _line_of(text: str, needle: str) -> int:
    return text[: text.index(needle)].count("\n") + 1


MALFORMED = [
    ("not xml", "this is not XML at all", None, "not well-formed XML"),
    ("empty file", "", 1, "not well-formed XML"),
    ("unclosed tag", GOOD.replace("</OpenDRIVE>", ""), None, "not well-formed XML"),
    ("wrong root", '<?xml version="1.0"?>\n<road/>', 2, "not <OpenDRIVE>"),
    ("no roads", '<OpenDRIVE><header revMajor="1" revMinor="6"/></OpenDRIVE>', 1, "no <road>"),
    ("revision 2", _case('revMajor="1"', 'revMajor="2"'), "<header", "not supported"),
    ("missing length", _case('length="100.0" junction', "junction"), "<road ", "no `length`"),
    (
        "length not a number",
        _case('length="100.0" junction', 'length="long" junction'),
        "<road ",
        "not a number: 'long'",
    ),
    ("hdg not a number", _case('hdg="0"', 'hdg="north"'), "<geometry", "`hdg` is not a number"),
    (
        "unknown geometry",
        _case("<line/>", "<clothoid/>"),
        "<clothoid",
        "unknown geometry <clothoid>",
    ),
    ("empty geometry", _case("<line/>", ""), "<geometry", "has no line, arc"),
    ("arc without curvature", _case("<line/>", "<arc/>"), "<arc", "no `curvature`"),
    (
        "no planView",
        _case("<planView>", "<planViewX>").replace("</planView>", "</planViewX>"),
        "<road ",
        "no <planView>",
    ),
    (
        "empty road",
        _case('<geometry s="0" x="0" y="0" hdg="0" length="100.0"><line/></geometry>', ""),
        "<road ",
        "no geometry",
    ),
    ("no lane section", GOOD.replace(LANES_2, ""), "<road ", "no <laneSection>"),
    (
        "lane without width",
        _case(WIDTH + "</lane></right>", "</lane></right>"),
        '<lane id="-1"',
        "neither <width> nor <border>",
    ),
    (
        "lane on wrong side",
        _case('<lane id="-1" type="driving">', '<lane id="2" type="driving">'),
        '<lane id="2"',
        "ids are negative",
    ),
    (
        "lane id gap",
        _case('<lane id="-1" type="driving">', '<lane id="-3" type="driving">'),
        "<laneSection",
        "count 1, 2",
    ),
    (
        "lane id not integer",
        _case('<lane id="-1" type="driving">', '<lane id="minus one" type="driving">'),
        '<lane id="minus',
        "not a number",
    ),
    ("bad rule", _case('junction="-1" ', 'junction="-1" rule="middle" '), "<road ", "RHT or LHT"),
    (
        "link to missing road",
        _case(
            "<planView>",
            '<link><successor elementType="road" elementId="99" contactPoint="start"/></link>\n'
            "    <planView>",
        ),
        "<successor",
        "road `99`, which does not exist",
    ),
    (
        "link to missing junction",
        _case(
            "<planView>",
            '<link><predecessor elementType="junction" elementId="5"/></link>\n    <planView>',
        ),
        "<predecessor",
        "junction `5`, which does not exist",
    ),
    (
        "bad link type",
        _case(
            "<planView>",
            '<link><successor elementType="bridge" elementId="1"/></link>\n    <planView>',
        ),
        "<successor",
        "road or junction",
    ),
    (
        "road in missing junction",
        _case('junction="-1"', 'junction="4"'),
        "<road ",
        "junction `4`, which does not exist",
    ),
    (
        "junction to missing road",
        GOOD.replace(
            "</OpenDRIVE>",
            '<junction id="9"><connection id="0" incomingRoad="1" connectingRoad="77" '
            'contactPoint="start"/></junction>\n</OpenDRIVE>',
        ),
        "<connection",
        "connecting road `77` does not exist",
    ),
    (
        "duplicate road",
        GOOD.replace("</OpenDRIVE>", road_xml() + "\n</OpenDRIVE>"),
        None,
        "used twice",
    ),
    ("infinite value", _case('x="0"', 'x="inf"'), "<geometry", "not finite"),
    (
        "bad pRange",
        _case(
            "<line/>",
            '<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0" pRange="metres"/>',
        ),
        "<paramPoly3",
        "arcLength or normalized",
    ),
]


@pytest.mark.parametrize(
    ("label", "text", "where", "problem"), MALFORMED, ids=[c[0] for c in MALFORMED]
)
def test_malformed_file_raises_map_error_at_its_line(
    write_map: WriteMap, label: str, text: str, where: str | int | None, problem: str
) -> None:
    path = write_map(text)
    with pytest.raises(MapError) as caught:
        load_opendrive(path)
    error = caught.value
    assert problem in error.problem, str(error)
    assert str(path) in str(error)
    if isinstance(where, str):
        assert error.line == _line_of(text, where), str(error)
        assert error.column is None or error.column >= 1
    elif isinstance(where, int):
        assert error.line == where
    assert str(error).startswith(f"{path}:")


def test_missing_file_raises_map_error(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="cannot read"):
        load_opendrive(tmp_path / "absent.xodr")


def test_column_points_at_the_element(write_map: WriteMap) -> None:
    text = _case("<line/>", "<clothoid/>")
    with pytest.raises(MapError) as caught:
        load_opendrive(write_map(text))
    line = text.splitlines()[caught.value.line - 1]
    assert line[caught.value.column - 1 :].startswith("<clothoid")


def test_link_to_missing_lane_is_a_warning_not_an_error(write_map: WriteMap) -> None:
    a = road_xml(
        "1", extra='<link><successor elementType="road" elementId="2" contactPoint="start"/></link>'
    )
    a = a.replace(
        '<lane id="-1" type="driving">',
        '<lane id="-1" type="driving"><link><successor id="-5"/></link>',
    )
    b = road_xml("2").replace('x="0" y="0"', 'x="100" y="0"')
    net = load_opendrive(write_map(xodr(a, b)))
    assert len(net.warnings) == 1 and "lane -5" in str(net.warnings[0])
    assert net.next_lanes(LaneRef("1", 0, -1)) == ()


def test_elevation_profile_is_read_as_cubics(write_map: WriteMap) -> None:
    extra = (
        '<elevationProfile><elevation s="0" a="1" b="0.01" c="0" d="0"/>'
        '<elevation s="50" a="1.5" b="0" c="0.001" d="0"/></elevationProfile>'
    )
    road = road_xml().replace("    <planView>", f"    {extra}\n    <planView>")
    net = load_opendrive(write_map(xodr(road)))
    z = net.roads["1"].elevation_at(np.array([0.0, 20.0, 50.0, 60.0]))
    assert np.allclose(z, [1.0, 1.2, 1.5, 1.5 + 0.001 * 100])


def test_lht_numbering_counts_from_the_right_in_travel_direction(write_map: WriteMap) -> None:
    lanes = f"""
      <laneSection s="0">
        <left>
          <lane id="3" type="sidewalk">{WIDTH}</lane>
          <lane id="2" type="driving">{WIDTH}</lane>
          <lane id="1" type="driving">{WIDTH}</lane>
        </left>
        <center><lane id="0" type="none"/></center>
        <right>
          <lane id="-1" type="driving">{WIDTH}</lane>
          <lane id="-2" type="driving">{WIDTH}</lane>
        </right>
      </laneSection>"""
    net = load_opendrive(write_map(xodr(road_xml(lanes=lanes, attrs='rule="LHT"'))))
    # Left lanes drive along +s under LHT; the right of that direction is towards the centre.
    assert net.osc2_lane_index(LaneRef("1", 0, 1)) == 1
    assert net.osc2_lane_index(LaneRef("1", 0, 2)) == 2
    assert net.osc2_lane_index(LaneRef("1", 0, 2), "left") == 1
    # Right lanes drive against s: travelling -x, the right is +y, towards the centre line:
    # under left-hand traffic the lane next to oncoming traffic is the rightmost.
    assert net.osc2_lane_index(LaneRef("1", 0, -1)) == 1
    assert net.osc2_lane_index(LaneRef("1", 0, -2)) == 2
    assert net.lane_from_osc2_index("1", 5.0, 1, direction=1) == LaneRef("1", 0, 1)
    assert net.lane_from_osc2_index("1", 5.0, 2, direction=-1) == LaneRef("1", 0, -2)
    with pytest.raises(ValueError, match="not a driving lane"):
        net.osc2_lane_index(LaneRef("1", 0, 3))
    n = net.neighbours(LaneRef("1", 0, 1))
    assert n.left == LaneRef("1", 0, 2) and n.right == LaneRef("1", 0, -1)
    assert n.left_same_direction and not n.right_same_direction


def test_lane_graph_across_sections_and_a_road_joined_end_to_end(write_map: WriteMap) -> None:
    # Road 1 (0..100, +x) has two sections; a right lane -2 opens at s=60. Road 2 runs
    # back from x=200 to x=100, so road 1's end meets road 2's end (contactPoint="end").
    sections = f"""
      <laneSection s="0">
        <left><lane id="1" type="driving">{WIDTH}<link><predecessor id="1"/></link></lane></left>
        <center><lane id="0" type="none"/></center>
        <right><lane id="-1" type="driving">{WIDTH}<link><successor id="-1"/></link></lane></right>
      </laneSection>
      <laneSection s="60">
        <left><lane id="1" type="driving">{WIDTH}<link><predecessor id="1"/>
          <successor id="-1"/></link></lane></left>
        <center><lane id="0" type="none"/></center>
        <right>
          <lane id="-1" type="driving">{WIDTH}<link><predecessor id="-1"/>
            <successor id="1"/></link></lane>
          <lane id="-2" type="shoulder">{WIDTH}</lane>
        </right>
      </laneSection>"""
    one = road_xml(
        "1",
        lanes=sections,
        extra='<link><successor elementType="road" elementId="2" contactPoint="end"/></link>',
    )
    two = road_xml(
        "2", extra='<link><successor elementType="road" elementId="1" contactPoint="end"/></link>'
    ).replace('x="0" y="0" hdg="0"', f'x="200" y="0" hdg="{math.pi}"')
    two = two.replace(
        '<lane id="1" type="driving">',
        '<lane id="1" type="driving"><link><successor id="-1"/></link>',
    ).replace(
        '<lane id="-1" type="driving">',
        '<lane id="-1" type="driving"><link><successor id="1"/></link>',
    )
    net = load_opendrive(write_map(xodr(one, two)))
    a0, a1 = LaneRef("1", 0, -1), LaneRef("1", 1, -1)
    assert net.next_lanes(a0) == (a1,)
    assert net.previous_lanes(a1) == (a0,)
    # Driving +x out of road 1 enters road 2 at its end: road 2's left lane drives -s there.
    assert net.next_lanes(a1) == (LaneRef("2", 0, 1),)
    assert net.previous_lanes(LaneRef("2", 0, 1)) == (a1,)
    # And back: road 2's right lane (towards x=100) leads into road 1's left lane.
    assert net.next_lanes(LaneRef("2", 0, -1)) == (LaneRef("1", 1, 1),)
    assert net.next_lanes(LaneRef("1", 1, 1)) == (LaneRef("1", 0, 1),)
    route = net.route(a0)
    assert route.lanes == (a0, a1, LaneRef("2", 0, 1)) and route.end == "dead_end"
    assert route.path.length == pytest.approx(200.0)
    assert route.path.x[-1] == pytest.approx(200.0) and route.path.y[-1] == pytest.approx(-1.75)
    spans = net.reachable(a0, 50.0, 60.0)
    assert [(span.lane, span.distance) for span in spans] == [
        (a0, 0.0),
        (a1, pytest.approx(10.0)),
        (LaneRef("2", 0, 1), pytest.approx(50.0)),
    ]
    assert spans[-1].s_from == pytest.approx(100.0) and spans[-1].s_to == pytest.approx(90.0)
    # Drivable surface by type: the shoulder opens at s=60.
    x = np.array([30.0, 80.0])
    y = np.array([-5.0, -5.0])
    assert list(net.on_drivable(x, y)) == [False, False]
    assert list(net.on_drivable(x, y, frozenset({"shoulder"}))) == [False, True]
