"""Helpers for the road-network tests: where the shared maps are, small maps as text."""

from __future__ import annotations

from pathlib import Path

import pytest

# tests/osc2check/world/conftest.py -> repository root is parents[3]; shared/ is its sibling.
SHARED_MAPS = Path(__file__).resolve().parents[3] / ".." / "shared" / "conformance" / "opendrive"
BUNDLED_MAPS = Path(__file__).resolve().parents[3] / "examples" / "maps"


def shared_maps() -> list[Path]:
    """The shared conformance maps, or an empty list when the folder is absent."""
    return sorted(SHARED_MAPS.glob("*.xodr")) if SHARED_MAPS.is_dir() else []


def shared_map(name: str) -> Path:
    """One shared map; skips the test when the shared folder is absent."""
    path = SHARED_MAPS / name
    if not path.is_file():
        pytest.skip(f"{path} is not present (../shared is not checked out)")
    return path


WIDTH = '<width sOffset="0" a="3.5" b="0" c="0" d="0"/>'
LANES_2 = f"""
      <laneSection s="0">
        <left><lane id="1" type="driving">{WIDTH}</lane></left>
        <center><lane id="0" type="none"/></center>
        <right><lane id="-1" type="driving">{WIDTH}</lane></right>
      </laneSection>"""


def road_xml(
    road_id: str = "1",
    length: float = 100.0,
    geometry: str = "<line/>",
    lanes: str = LANES_2,
    extra: str = "",
    attrs: str = "",
    lanes_extra: str = "",
) -> str:
    """One ``<road>`` starting at the origin heading +x."""
    return f"""  <road id="{road_id}" length="{length}" junction="-1" {attrs}>
    {extra}
    <planView>
      <geometry s="0" x="0" y="0" hdg="0" length="{length}">{geometry}</geometry>
    </planView>
    <lanes>{lanes_extra}{lanes}
    </lanes>
  </road>"""


def xodr(*roads: str, tail: str = "") -> str:
    """A whole OpenDRIVE 1.8 document around ``roads`` (and junctions in ``tail``)."""
    body = "\n".join(roads)
    return f"""<?xml version="1.0" encoding="utf-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="8" name="test"/>
{body}
{tail}
</OpenDRIVE>
"""


def scenario_on(map_file: str, speed: str = "50kph") -> str:
    """A scenario whose one vehicle drives on the map ``map_file`` (a relative path)."""
    return f"""import osc.standard
scenario s:
    town: map with:
        keep(it.map_file == "{map_file}")
    hero: vehicle
    do hero.drive(duration: 3s) with:
        speed({speed})
"""


def one_lane(side: str, width: str) -> str:
    """A lane section with one driving lane of ``width`` on ``side`` (``left``/``right``)."""
    lane_id = 1 if side == "left" else -1
    width_record = f'<width sOffset="0" a="{width}" b="0" c="0" d="0"/>'
    return f"""
      <laneSection s="0">
        <{side}><lane id="{lane_id}" type="driving">{width_record}</lane></{side}>
        <center><lane id="0" type="none"/></center>
      </laneSection>"""
