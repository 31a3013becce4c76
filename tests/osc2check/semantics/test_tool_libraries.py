"""Other tools' libraries: `osc.*` modules from the module map or the search paths, and
struct values built by calling the struct's name (scenario_execution's dialect).

The scenario_execution tests read its public repository from the folder named by
``OSC2_THIRD_PARTY`` (``<folder>/scenario_execution``) and skip without it. Its
scenarios are robotics; the ones about driving are the mobile robot's navigation
(``nav_to_pose``, ``nav_through_poses``, with the simulation that spawns obstacles
in its way): they are the road-traffic-like ones checked here, with ``hello_world``
and ``test_log`` for the ``log`` action, which the example plug-in implements
(``examples/plugins/example_plugin.py``; without it, each call is A308).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.config import config_from_mapping

EXAMPLE_PLUGIN = str(Path(__file__).parents[3] / "examples" / "plugins" / "example_plugin.py")

HELPERS = """\
action log:
    msg: string
"""

GREETING = """\
import osc.helpers

scenario hello:
    do log("hello")
"""


def findings(path: Path, **options: object) -> list[tuple[str, str]]:
    text = path.read_text(encoding="utf-8")
    analysis = analyze([SourceInput(str(path), text)], AnalysisOptions(**options))  # type: ignore[arg-type]
    return [(d.code.code, d.message) for d in analysis.diagnostics]


def codes(path: Path, **options: object) -> list[str]:
    return [code for code, _ in findings(path, **options)]


@pytest.mark.parametrize("layout", ["osc/helpers.osc", "helpers.osc"])
def test_an_osc_module_is_found_in_the_search_paths_with_a_warning(tmp_path, layout):
    library = tmp_path / "lib_osc" / layout
    library.parent.mkdir(parents=True)
    library.write_text(HELPERS, encoding="utf-8")
    scenario = tmp_path / "s.osc"
    scenario.write_text(GREETING, encoding="utf-8")
    ((code, message),) = findings(
        scenario, search_paths=(str(tmp_path / "lib_osc"),), plugins=(EXAMPLE_PLUGIN,)
    )
    assert code == "D810" and str(library) in message


def test_the_module_map_names_the_file_and_says_it_is_meant(tmp_path):
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "anything.osc").write_text(HELPERS, encoding="utf-8")
    (tmp_path / "osc2check.toml").write_text(
        '[modules]\n"osc.helpers" = "lib/anything.osc"\n', encoding="utf-8"
    )
    scenario = tmp_path / "s.osc"
    scenario.write_text(GREETING, encoding="utf-8")
    from osc2check.config import load_config

    config, _ = load_config(tmp_path)
    assert config.modules == {"osc.helpers": str(tmp_path / "lib" / "anything.osc")}
    options = config.analysis_options(plugins=(EXAMPLE_PLUGIN,))
    analysis = analyze([SourceInput(str(scenario), GREETING)], options)
    assert analysis.diagnostics == []
    # no plug-in implements `log`: the runner would not run it
    analysis = analyze([SourceInput(str(scenario), GREETING)], config.analysis_options())
    assert [(d.code.code, d.span.line) for d in analysis.diagnostics] == [("A308", 4)]


def test_an_osc_module_found_nowhere_is_unresolved_and_says_where_to_name_it(tmp_path):
    scenario = tmp_path / "s.osc"
    scenario.write_text(GREETING, encoding="utf-8")
    (code, message), *_ = findings(scenario)
    assert code == "N105" and "[tool.osc2check.modules]" in message


STRUCTS = """\
import osc.standard

action vehicle.go_to inherits vehicle.action_for_vehicle:
    goal: pose_3d

scenario s:
    car: vehicle
    do car.go_to({goal})
"""


@pytest.mark.parametrize(
    ("goal", "expected"),
    [
        ("pose_3d(position_3d(x: 1m, y: 2m))", ["D809", "D809"]),
        ("pose_3d(position_3d(1m, 2m, 0m), orientation_3d(yaw: 1rad))", ["D809"] * 3),
        ("pose_3d(position: position_3d(z: 1m))", ["D809", "D809"]),
        ("pose_3d(position_3d(x: 1m, w: 2m))", ["D809", "D809", "A302"]),
        ("pose_3d(position_3d(x: 1kph))", ["D809", "D809", "T201"]),
        ("pose_3d(position_3d(1m, 2m, 3m, 4m))", ["D809", "D809", "A304"]),
        ("position_3d(x: 1m)", ["D809", "T203"]),
    ],
)
def test_a_struct_is_built_from_its_fields_in_declaration_order(tmp_path, goal, expected):
    scenario = tmp_path / "s.osc"
    scenario.write_text(STRUCTS.format(goal=goal), encoding="utf-8")
    # go_to is the user's action, which no plug-in implements here (A308)
    assert sorted(c for c in codes(scenario) if c not in ("L506", "A308")) == sorted(expected)


# ---- scenario_execution's own files --------------------------------------------------

THIRD_PARTY = os.environ.get("OSC2_THIRD_PARTY")
needs_third_party = pytest.mark.skipif(
    not THIRD_PARTY or not (Path(THIRD_PARTY) / "scenario_execution").is_dir(),
    reason="OSC2_THIRD_PARTY does not name a folder with scenario_execution",
)
NAVIGATION = [
    "examples/example_nav2/example_nav2.osc",
    "examples/example_simulation/scenarios/example_simulation.osc",
    "examples/example_multi_robot/scenarios/example_multi_robot.osc",
    "examples/example_scenario_control/scenarios/init_nav2.osc",
    "examples/example_scenario_control/scenarios/nav2_pose_1.osc",
    "examples/example_scenario_control/scenarios/nav2_pose_2.osc",
]
LOGGING = [
    "examples/example_scenario/hello_world.osc",
    "scenario_execution_coverage/scenarios/test_log.osc",
]


def module_map(root: Path) -> dict[str, object]:
    """``osc.<name>`` -> each ``lib_osc/<name>.osc`` of the repository, as a user writes
    it in ``[tool.osc2check.modules]``; the standard's own modules stay the toolkit's."""
    modules = {f"osc.{p.stem}": str(p) for p in sorted(root.glob("**/lib_osc/*.osc"))}
    modules.pop("osc.standard")
    return {"modules": modules}


@needs_third_party
@pytest.mark.parametrize("name", NAVIGATION + LOGGING)
def test_scenario_execution_scenarios_check_without_errors_with_a_module_map(name):
    root = Path(THIRD_PARTY or "") / "scenario_execution"
    config = config_from_mapping({**module_map(root), "plugins": [EXAMPLE_PLUGIN]})
    path = root / name
    analysis = analyze([SourceInput(str(path), path.read_text())], config.analysis_options())
    found = {d.code.code for d in analysis.diagnostics}
    # struct constructors (D809) and unit-less lengths (D805) are its dialect's forms; its
    # robots' actions (nav_to_pose, ...) are behaviours no plug-in implements (A308)
    assert found <= {"D809", "D805", "A308"}, [str(d) for d in analysis.diagnostics]
    for d in analysis.diagnostics:
        assert d.code.code != "A308" or "no plug-in implements it" in d.message
    if name in LOGGING:
        assert found == set()  # `log` is the example plug-in's
