"""Traffic-light control files (ASAM OpenSCENARIO DSL 2.1 §8.12.2.2,
``map.set_traffic_lights_control_file``), in the OpenSCENARIO XML format of signal
plans: each controller's phases run in order for their durations, round and round,
from its delay (plus its reference's); the lights change at the ticks that
arithmetic gives."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.errors import ScenarioError
from tests.osc2runner.behaviours.test_actions_world import _light_changes as _changes

JUNCTION = Path(__file__).resolve().parents[3] / "examples" / "maps" / "four_way_junction.xodr"

PLANS = """\
<?xml version="1.0"?>
<OpenSCENARIO>
  <RoadNetwork>
    <TrafficSignals>
      <TrafficSignalController name="ew" delay="1">
        <Phase name="go" duration="4">
          <TrafficSignalState trafficSignalId="tl1" state="go"/>
          <TrafficSignalState trafficSignalId="tl9" state="go"/>
        </Phase>
        <Phase name="attention" duration="2">
          <TrafficSignalState trafficSignalId="tl1" state="{attention}"/>
        </Phase>
        <Phase name="stop" duration="4">
          <TrafficSignalState trafficSignalId="tl1" state="stop"/>
        </Phase>
      </TrafficSignalController>
      <TrafficSignalController name="ns" delay="0.5" reference="ew">
        <Phase name="stop" duration="6">
          <TrafficSignalState trafficSignalId="north" state="on;off;off"/>
        </Phase>
        <Phase name="go" duration="4">
          <TrafficSignalState trafficSignalId="north" state="go"/>
        </Phase>
      </TrafficSignalController>
    </TrafficSignals>
  </RoadNetwork>
</OpenSCENARIO>
"""

SCENARIO = f"""\
import osc.standard

scenario s:
    town: map with:
        keep(it.map_file == "{JUNCTION.as_posix()}")
    town.set_traffic_lights_control_file("{{file}}")
    ctrl: traffic_light_controller
    east: traffic_light with:
        keep(it.map_id == "tl1")
    north: traffic_light with:
        keep(it.pose.position.x == 10m)
        keep(it.pose.position.y == 10m)
    do serial:
        wait elapsed(2s)
        ctrl.set_semantic_state(traffic_light: east, state: stop)
        wait elapsed(10s)
"""


def _run(tmp_path: Path, attention: str = "off;on;off", file: str = "plans.xosc"):
    (tmp_path / "plans.xosc").write_text(PLANS.format(attention=attention))
    source = tmp_path / "s.osc"
    source.write_text(SCENARIO.replace("{file}", file))
    return run(source)


def test_the_plans_switch_the_lights_at_their_phases(tmp_path: Path):
    result = _run(tmp_path)
    assert result.outcome.status == "success", result.outcome.reason
    # ew from 1 s: go 4 s, attention 2 s, stop 4 s, round again at 11 s; the controller's
    # stop at 2 s holds until the plan's next phase (5 s)
    assert _changes(result, "east") == [
        (1.0, "go"),
        (2.0, "stop"),
        (5.0, "attention"),
        (7.0, "stop"),
        (11.0, "go"),
    ]
    # ns starts 0.5 s after ew's start (its reference): stop 6 s, go 4 s; north has no
    # map_id and is named by its parameter
    assert _changes(result, "north") == [(1.5, "stop"), (7.5, "go"), (11.5, "stop")]
    assert (
        "control file plans.xosc: signal 'tl9' is not a traffic light of the scenario"
        in (result.metadata["notes"])
    )


def test_a_state_the_light_cannot_show_is_an_error_at_its_place_in_the_file(tmp_path: Path):
    with pytest.raises(ScenarioError) as caught:
        _run(tmp_path, attention="off;on")
    text = str(caught.value.problems[0])
    assert ":6:42: error: traffic-light control file: " in text  # the modifier's string
    assert f"{tmp_path / 'plans.xosc'}:11:11: state 'off;on' is neither" in text


def test_a_missing_control_file_is_an_error_at_its_name(tmp_path: Path):
    with pytest.raises(ScenarioError) as caught:
        _run(tmp_path, file="missing.xosc")
    assert "cannot read the control file" in str(caught.value.problems[0])
