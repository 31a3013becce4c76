"""Maps held to what a road can be (``osc2check.world.budget``): a record beyond it, or a
map beyond the sample budget, is a ``MapError`` at its element, found before anything is
sampled at its cost; every other file is still checked.

A 600-byte map with an arc of curvature 1e6 took gigabytes; a road 1e7 m long took 2.7
GB; 1e9 and 1e300 were internal errors that lost every file's findings; a paramPoly3
with coefficients of 1e300 passed the checker and crashed the runner; a folder, FIFO or
device named ``*.xodr`` was "no such file"; a map had no size limit. A seeded storm of
geometry records of every magnitude ends in a network of finite samples within the
limits, or in a MapError, never in anything else.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from osc2check import cli
from osc2check.world import budget
from osc2check.world.errors import MapError
from osc2check.world.maps import load_map
from osc2check.world.opendrive import load_opendrive
from tests.osc2check.world.maptext import one_lane, road_xml, scenario_on, xodr


def _refused(path: Path) -> MapError:
    with pytest.raises(MapError) as caught:
        load_opendrive(path)
    return caught.value


@pytest.mark.parametrize(
    ("geometry", "length", "problem"),
    [
        ('<arc curvature="1e6"/>', 10, "bends more sharply than a road can: curvature 1e+06"),
        ('<arc curvature="-11"/>', 10, "bends more sharply"),
        ('<spiral curvStart="0" curvEnd="50"/>', 10, "bends more sharply"),
        ("<line/>", 2e5, "longer than a road can be"),
        ("<line/>", 1e9, "longer than a road can be"),
        ("<line/>", 1e300, "longer than a road can be"),
        (
            '<paramPoly3 aU="0" bU="1" cU="0" dU="1e300" aV="0" bV="0" cV="0" dV="1e300" '
            'pRange="arcLength"/>',
            50,
            "paramPoly3 at s=0",
        ),
        (
            '<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="10" dV="0" '
            'pRange="normalized"/>',
            50,
            "paramPoly3 at s=0 bends more sharply",
        ),
        ('<poly3 a="0" b="0" c="0" d="1e200"/>', 50, "poly3 at s=0"),
    ],
)
def test_a_geometry_beyond_what_a_road_can_be_is_refused_at_its_line(
    write_map, geometry, length, problem
):
    text = xodr(road_xml(length=length, geometry=geometry))
    error = _refused(write_map(text))
    assert problem in error.problem
    assert error.line is not None and error.line <= text.count("\n")


def test_a_geometry_far_from_the_origin_is_refused(write_map):
    text = xodr(road_xml()).replace('x="0" y="0"', 'x="1e12" y="0"')
    assert "starts at (1e+12, 0)" in _refused(write_map(text)).problem


def test_a_lane_wider_than_any_road_is_refused_at_its_section(write_map):
    error = _refused(write_map(xodr(road_xml(lanes=one_lane("left", "1e6")))))
    assert "lies 1e+06 m beside the reference line" in error.problem


def test_a_road_elevated_beyond_any_is_refused(write_map):
    elevation = '<elevationProfile><elevation s="0" a="0" b="0" c="0" d="1e9"/></elevationProfile>'
    error = _refused(write_map(xodr(road_xml(extra=elevation))))
    assert "its elevation reaches" in error.problem


def test_a_map_beyond_the_sample_budget_is_refused_naming_the_road(write_map, monkeypatch):
    """Forty roads of 90 km fit each alone; together they need 3.6 million samples."""
    monkeypatch.setattr(budget, "MAX_SAMPLES", 50_000)  # the same rule, at a test's size
    roads = [road_xml(str(i), length=2_000).replace('y="0"', f'y="{50 * i}"') for i in range(40)]
    error = _refused(write_map(xodr(*roads)))
    assert "needs more than 50,000 samples" in error.problem
    assert error.problem.startswith("road `24`")


def test_a_map_beyond_the_border_budget_is_refused(write_map, monkeypatch):
    monkeypatch.setattr(budget, "MAX_BORDER_VALUES", 10_000)
    error = _refused(write_map(xodr(road_xml(length=5_000))))
    assert "lane-border values" in error.problem


def test_a_map_beyond_the_road_surface_budget_is_refused(write_map, monkeypatch):
    """What the runner's grid covers: a short road with a lane 400 m wide is no cheaper
    than a long narrow one."""
    monkeypatch.setattr(budget, "MAX_ROAD_AREA", 20_000.0)
    assert (
        "km² of road surface"
        in _refused(write_map(xodr(road_xml(lanes=one_lane("right", "400"))))).problem
    )
    load_opendrive(write_map(xodr(road_xml()), "narrow.xodr"))  # 100 m of two lanes: 1,300 m²


def test_a_map_file_over_the_size_limit_is_refused_unread(tmp_path):
    path = tmp_path / "huge.xodr"
    with open(path, "wb") as huge:  # sparse: no disk used, never read
        huge.truncate(budget.MAX_MAP_BYTES + 1)
    assert "too large" in _refused(path).problem


def test_a_map_with_too_many_elements_is_refused(write_map, monkeypatch):
    monkeypatch.setattr("osc2check.world.opendrive.xmltree.MAX_MAP_ELEMENTS", 20)
    error = _refused(write_map(xodr(road_xml("1"), road_xml("2"))))
    assert "more than 20 elements" in error.problem and error.line is not None


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="FIFOs and /dev/null")
def test_a_folder_fifo_or_device_named_xodr_is_said_to_be_so(tmp_path):
    (tmp_path / "folder.xodr").mkdir()
    os.mkfifo(tmp_path / "pipe.xodr")  # opened for reading, it would block
    (tmp_path / "null.xodr").symlink_to("/dev/null")
    for name, what in [
        ("folder.xodr", "a folder, not a file"),
        ("pipe.xodr", "a named pipe"),
        ("null.xodr", "a character device"),
    ]:
        with pytest.raises(MapError) as caught:
            load_map(name, tmp_path)
        assert what in str(caught.value) and "no such file" not in str(caught.value)
    with pytest.raises(MapError, match="no such file"):
        load_map("absent.xodr", tmp_path)


def test_one_bad_map_never_removes_the_findings_of_the_other_files(tmp_path):
    """A road of 1e300 m was an internal error: no output at all, for any file."""
    (tmp_path / "bad.xodr").write_text(xodr(road_xml(length=1e300)), encoding="utf-8")
    (tmp_path / "good.xodr").write_text(xodr(road_xml(length=300)), encoding="utf-8")
    (tmp_path / "bad.osc").write_text(scenario_on("bad.xodr"), encoding="utf-8")
    (tmp_path / "good.osc").write_text(scenario_on("good.xodr", speed="500kph"), encoding="utf-8")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = cli.main(
            [str(tmp_path / "bad.osc"), str(tmp_path / "good.osc"), "--output-format", "json"]
        )
    found = {
        (Path(f["location"]["path"]).name, f["code"])
        for f in json.loads(out.getvalue())["findings"]
    }
    assert ("bad.osc", "L516") in found
    assert ("good.osc", "L508") in found  # 500 kph: the good file is checked all the same
    assert status == 1


# ---- a seeded storm of geometry records of every magnitude ---------------------------------

_MAGNITUDES = st.sampled_from([0.0, 1e-9, 0.01, 0.5, 1.0, 3.0, 50.0, 1e3, 1e5, 1e7, 1e150, 1e300])
_SIGNED = st.tuples(_MAGNITUDES, st.sampled_from([1.0, -1.0])).map(lambda v: v[0] * v[1])


@st.composite
def geometries(draw) -> tuple[str, float]:
    kind = draw(st.sampled_from(["line", "arc", "spiral", "poly3", "paramPoly3"]))
    length = draw(st.sampled_from([0.01, 1.0, 37.5, 500.0, 2e5, 1e9]))
    if kind == "line":
        return "<line/>", length
    if kind == "arc":
        return f'<arc curvature="{draw(_SIGNED)}"/>', length
    if kind == "spiral":
        return f'<spiral curvStart="{draw(_SIGNED)}" curvEnd="{draw(_SIGNED)}"/>', length
    if kind == "poly3":
        a, b, c, d = (draw(_SIGNED) for _ in range(4))
        return f'<poly3 a="{a}" b="{b}" c="{c}" d="{d}"/>', length
    names = ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV")
    values = " ".join(f'{n}="{draw(_SIGNED)}"' for n in names)
    p_range = draw(st.sampled_from(["arcLength", "normalized"]))
    return f'<paramPoly3 {values} pRange="{p_range}"/>', length


@pytest.mark.filterwarnings("error")  # overflow is refused, never warned about
@settings(max_examples=200, derandomize=True, deadline=None)
@given(record=geometries(), width=_SIGNED)
def test_map_storm_every_record_is_read_within_the_limits_or_refused(
    tmp_path_factory, record, width
):
    geometry, length = record
    lanes = one_lane("right", str(width))
    path = tmp_path_factory.mktemp("storm") / "map.xodr"
    path.write_text(xodr(road_xml(length=length, geometry=geometry, lanes=lanes)), encoding="utf-8")
    try:
        network = load_opendrive(path)
    except MapError as error:
        assert error.line is not None and str(path) in str(error)
        return
    for road in network.roads.values():
        assert len(road.s) <= budget.MAX_SAMPLES
        for values, limit in ((road.x, budget.MAX_COORDINATE), (road.y, budget.MAX_COORDINATE)):
            assert np.all(np.isfinite(values)) and np.all(np.abs(values) <= limit)
        assert np.all(np.abs(road.curvature) <= budget.MAX_CURVATURE)
        for section in road.sections:
            assert np.all(np.abs(np.asarray(section.borders)) <= budget.MAX_LATERAL)
