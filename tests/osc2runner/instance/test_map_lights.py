"""Traffic lights on an OpenDRIVE map: a light whose ``map_id`` names a dynamic
``<signal>`` stands where the map puts it and is in the group of the map's
``<controller>``; an id the map does not have stops the run before it starts."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.world.maps import load_map
from osc2runner import run
from osc2runner.errors import ScenarioError

JUNCTION = Path(__file__).resolve().parents[3] / "examples" / "maps" / "four_way_junction.xodr"

SCENARIO = f"""\
import osc.standard

scenario lights_on_map:
    town: map with:
        keep(it.map_file == "{JUNCTION.as_posix()}")
    ctrl: traffic_light_controller
    east: traffic_light with:
        keep(it.map_id == "tl1")
    west: traffic_light with:
        keep(it.map_id == "{{west}}")
    north: traffic_light with:
        keep(it.map_id == "tl2")
    do serial:
        ctrl.set_semantic_state(traffic_light: east, state: stop, sync: true)
        wait elapsed(1s)
        ctrl.set_semantic_state(traffic_light: east, state: go)
        wait elapsed(1s)
"""


def _run(tmp_path: Path, west: str = "tl3"):
    source = tmp_path / "lights.osc"
    source.write_text(SCENARIO.replace("{west}", west))
    return run(source, out=tmp_path / "out")


def test_a_light_with_a_map_id_stands_at_its_signal(tmp_path: Path) -> None:
    result = _run(tmp_path)
    assert result.outcome.status == "success", result.outcome.reason
    network = load_map(str(JUNCTION))
    signals = {s.id: s for s in network.signals}
    placed = result.metadata["traffic_lights"]
    for name, signal_id in (("east", "tl1"), ("west", "tl3"), ("north", "tl2")):
        pose = network.signal_pose(signals[signal_id])
        assert placed[name]["x"] == pytest.approx(pose.x, abs=1e-9)
        assert placed[name]["y"] == pytest.approx(pose.y, abs=1e-9)
        assert placed[name]["yaw"] == pytest.approx(pose.yaw, abs=1e-9)
        # beside the road, facing the traffic it is valid for
        point = network.to_road(pose.x, pose.y)
        assert point is not None and not point.drivable
    # groups are the map's controllers: tl1 and tl3 are switched by "ew", tl2 by "ns"
    assert [placed[n]["group"] for n in ("east", "west", "north")] == ["ew", "ew", "ns"]


def test_sync_switches_the_lights_of_the_same_map_controller(tmp_path: Path) -> None:
    result = _run(tmp_path)
    semantic = {name: list(result.lights[name]["semantic"]) for name in result.lights}
    assert semantic["east"][0] == semantic["west"][0] == "stop"  # synchronised: same group
    assert semantic["north"][0] == "off"  # the other controller's light is untouched
    assert semantic["east"][-1] == "go" and semantic["west"][-1] == "stop"  # sync: false


def test_a_map_id_the_map_does_not_have_is_an_error_at_the_light(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError) as caught:
        _run(tmp_path, west="tl9")
    text = "\n".join(str(p) for p in caught.value.problems)
    assert ":9:5: error:" in text and "lights.osc" in text
    assert "map_id 'tl9' is not a traffic light of the map" in text
    assert "tl1, tl2, tl3, tl4" in text


def test_a_light_the_map_does_not_have_stands_at_the_pose_the_scenario_gives(tmp_path: Path):
    """ASAM OpenSCENARIO DSL 2.1 §8.15: ``pose`` is a light's mandatory place, ``map_id``
    an optional id in the map; a light the map does not have is the scenario's own."""
    source = tmp_path / "lights.osc"
    source.write_text(
        SCENARIO.replace(
            'keep(it.map_id == "{west}")',
            'keep(it.map_id == "tl9")\n'
            "        keep(it.pose.position.x == 12m)\n"
            "        keep(it.pose.position.y == -7m)\n"
            "        keep(it.pose.orientation.yaw == 90deg)",
        )
    )
    result = run(source, out=tmp_path / "out")
    assert result.outcome.status == "success", result.outcome.reason
    west = result.metadata["traffic_lights"]["west"]
    assert (west["x"], west["y"], west["placed"]) == (12.0, -7.0, "pose")
    assert west["yaw"] == pytest.approx(1.5707963, abs=1e-6)
    assert west["group"] == ""  # in no controller's group: sync does not switch it
    assert list(result.lights["west"]["semantic"]) == ["off"] * len(result.lights["west"]["tick"])
    assert result.metadata["traffic_lights"]["east"]["placed"] == "signal"


def test_a_light_with_a_map_id_and_a_pose_stands_on_a_built_in_road(tmp_path: Path):
    source = tmp_path / "lights.osc"
    source.write_text(
        "import osc.standard\n\nscenario s:\n    ctrl: traffic_light_controller\n"
        "    tl: traffic_light with:\n"
        '        keep(it.map_id == "signal_7")\n'
        "        keep(it.pose.position.x == 80m)\n"
        "        keep(it.pose.position.y == -1m)\n"
        "    do serial:\n"
        "        ctrl.set_semantic_state(traffic_light: tl, state: stop)\n"
        "        wait elapsed(0.5s)\n"
    )
    result = run(source)
    assert result.outcome.status == "success", result.outcome.reason
    tl = result.metadata["traffic_lights"]["tl"]
    assert (tl["x"], tl["y"], tl["placed"]) == (80.0, -1.0, "pose")
    assert result.lights["tl"]["semantic"][-1] == "stop"
