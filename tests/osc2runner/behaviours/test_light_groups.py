"""The traffic-light group actions: `set_group_state` and `set_group_semantic_state`."""

from __future__ import annotations

from tests.osc2runner.behaviours.test_actions_world import LIGHT, run_text
from tests.osc2runner.behaviours.test_actions_world import _light_changes as _changes

GROUPS = """\
    north: traffic_light_group with:
        keep(it.map_id == "north")
    south: traffic_light_group with:
        keep(it.map_id == "south")
"""


def _run(tmp_path, body: str):
    return run_text(tmp_path, LIGHT + GROUPS + body)


def test_group_actions_set_every_light_of_the_group(tmp_path):
    result = _run(
        tmp_path,
        """\
    do serial:
        ctrl.set_group_semantic_state(traffic_light_group: north, state: go)
        wait elapsed(1s)
        ctrl.set_group_state(group: north, state: [is_on, is_off, is_off])
        wait elapsed(1s)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    for name in ("tl", "tl2"):
        assert _changes(result, name) == [(0.0, "go"), (1.0, "stop")]


def test_group_semantic_state_of_a_group_without_lights_fails(tmp_path):
    result = _run(
        tmp_path,
        """\
    do serial:
        ctrl.set_group_semantic_state(traffic_light_group: south, state: go)
""",
    )
    assert result.outcome.status == "failure"
    assert "no traffic light of the scenario is in this group" in result.outcome.reason
    assert _changes(result, "tl") == []


def test_group_state_of_a_group_without_lights_fails(tmp_path):
    result = _run(
        tmp_path,
        """\
    do serial:
        ctrl.set_group_state(group: south, state: [is_on, is_off, is_off])
""",
    )
    assert result.outcome.status == "failure"
    assert "no traffic light of the scenario is in this group" in result.outcome.reason
