"""The plug-in API wired into the checker and the runner (docs/plugins.md): what a
plug-in implements is known to the checker (no A308) and run by the runner; what no
plug-in implements is A308 in both; --plugin, [tool.osc2check] plugins and the entry
point group ``osc2toolkit.plugins`` load them."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from osc2check import plugins as plugin_api
from osc2check.analysis import SourceInput, analyze
from osc2check.config import ConfigError, config_from_mapping
from osc2runner import run
from osc2runner.cli import main as osc2run_main
from osc2runner.errors import ScenarioError

EXAMPLES = Path(__file__).parents[2] / "examples" / "plugins"
EXAMPLE_PLUGIN = str(EXAMPLES / "example_plugin.py")
GREETING = EXAMPLES / "greeting.osc"
KPH = 1 / 3.6


def with_plugins(*names: str):
    return config_from_mapping({"plugins": list(names)})


def test_the_greeting_logs_and_accelerates_through_the_example_plugin():
    result = run(GREETING, config=with_plugins(EXAMPLE_PLUGIN))
    assert result.outcome.status == "success", result.outcome.reason
    logs = [r.detail for r in result.events if r.kind == "log"]
    assert logs == ["Hello World!", "car accelerates to 60 kph", "Good Bye!"]
    # accelerate_to lasts until the car drives at 60 kph, at no more than 3 m/s²
    (start,) = result.event_ticks("start", "car.accelerate_to")
    (end,) = result.event_ticks("end", "car.accelerate_to")
    speed = result.telemetry["car"]["speed"]
    assert speed[start] == pytest.approx(30 * KPH, abs=0.3)
    assert abs(speed[end] - 60 * KPH) < 0.1
    assert np.all(np.diff(speed[start : end + 1]) / 0.05 <= 3.0 + 1e-6)
    # the second log starts when the driving action ended
    assert result.event_ticks("start", "log")[1] == end


def test_without_the_plugin_the_checker_and_the_runner_name_the_same_calls():
    text = GREETING.read_text(encoding="utf-8")
    analysis = analyze([SourceInput(str(GREETING), text)], with_plugins().analysis_options())
    checked = [(d.code.code, d.span.line, d.message) for d in analysis.diagnostics]
    assert [c[:2] for c in checked if c[0] == "A308"] == [("A308", 15), ("A308", 19), ("A308", 20)]
    with pytest.raises(ScenarioError) as caught:
        run(GREETING, config=with_plugins())
    refused = [(d.code.code, d.span.line, d.message) for d in caught.value.diagnostics]
    assert refused == [c for c in checked if c[0] == "A308"]
    assert "`vehicle.accelerate_to`" in refused[1][2]
    # with it, the checker finds nothing to say about them
    options = with_plugins(EXAMPLE_PLUGIN).analysis_options()
    analysis = analyze([SourceInput(str(GREETING), text)], options)
    assert {d.code.code for d in analysis.diagnostics} <= {"L506"}


OWN_PLUGIN = """
from osc2check.plugins import action, method, modifier


@method("vehicle", "is_fast")
def is_fast(run, subject, limit):
    return subject.speed > limit


@modifier("note", actor="vehicle")
class Note:
    def start(self, run, actor, text, every):
        self.text, self.every, self.next = text, every, run.time

    def step(self, run, actor):
        if run.time >= self.next - 1e-9:
            run.log(f"{self.text} {actor.name} {actor.speed * 3.6:.0f}")
            self.next += self.every


@action("shout")
def shout(run, msg, times):
    for _ in range(times):
        run.log(msg)


@action("fail_now", actor="vehicle")
def fail_now(run, actor):
    raise RuntimeError("no fuel")
"""

OWN_LIBRARY = """\
import osc.standard

extend vehicle:
    def is_fast(limit: speed) -> bool is undefined

modifier vehicle.note:
    text: string
    every: time = 1s

action shout:
    msg: string
    times: int = 2

action vehicle.fail_now inherits vehicle.action_for_vehicle
"""

OWN_SCENARIO = """\
import osc.standard
import "lib.osc"

scenario top:
    car: vehicle
    do serial:
        car.drive(duration: 20s) with:
            lane(1, at: start)
            speed(10kph, at: start)
            speed(60kph, at: end)
            note("car at")
            until rise(car.is_fast(40kph))
        shout("fast!")
"""


@pytest.fixture
def own(tmp_path):
    (tmp_path / "my_plugin.py").write_text(OWN_PLUGIN, encoding="utf-8")
    (tmp_path / "lib.osc").write_text(OWN_LIBRARY, encoding="utf-8")
    scenario = tmp_path / "top.osc"
    scenario.write_text(OWN_SCENARIO, encoding="utf-8")
    return scenario


def test_a_modifier_a_method_and_an_unbound_action_of_a_plugin_run(own):
    config = with_plugins(str(own.parent / "my_plugin.py"))
    text = own.read_text(encoding="utf-8")
    analysis = analyze([SourceInput(str(own), text)], config.analysis_options())
    assert {d.code.code for d in analysis.diagnostics} <= {"L506"}, analysis.diagnostics
    result = run(own, config=config)
    assert result.outcome.status == "success", result.outcome.reason
    speed = result.telemetry["car"]["speed"]
    # the method ends the drive when the car first drives faster than 40 kph
    (stop,) = result.event_ticks("stop", "car.drive")
    assert speed[stop] > 40 * KPH >= speed[stop - 1]
    # the modifier logs every 1 s (its default) of the phase, with the speed it reads
    logs = [(r.tick, r.detail) for r in result.events if r.kind == "log"]
    notes = [(tick, d) for tick, d in logs if d.startswith("car at")]
    assert [tick for tick, _ in notes] == list(range(0, stop, 20))
    assert [int(d.split()[-1]) for _, d in notes] == [round(speed[t] * 3.6) for t, _ in notes]
    # the action without an actor is instant: its default `times` logs twice, at once
    shouts = [tick for tick, d in logs if d == "fast!"]
    assert shouts == [stop, stop] == result.event_ticks("end", "shout") * 2


def test_the_method_is_a308_without_the_plugin(own):
    text = own.read_text(encoding="utf-8")
    analysis = analyze([SourceInput(str(own), text)], with_plugins().analysis_options())
    found = sorted(
        (d.span.line, d.message.split("`")[1])
        for d in analysis.diagnostics
        if d.code.code == "A308"
    )
    assert found == [(11, "vehicle.note"), (12, "vehicle.is_fast"), (13, "shout")]


def test_a_plugin_that_raises_fails_the_run_at_the_invocation(own):
    config = with_plugins(str(own.parent / "my_plugin.py"))
    text = OWN_SCENARIO.replace('        shout("fast!")\n', "        car.fail_now()\n")
    own.write_text(text, encoding="utf-8")
    result = run(own, config=config)
    assert result.outcome.status == "failure"
    assert (
        "top.osc:13:9: car.fail_now: the plug-in raised RuntimeError: no fuel"
        in result.outcome.reason
    )


def test_a_plugin_modifier_applied_to_the_whole_scenario_is_refused(own):
    config = with_plugins(str(own.parent / "my_plugin.py"))
    text = OWN_SCENARIO.replace("    car: vehicle\n", '    car: vehicle\n    car.note("x")\n')
    own.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError) as caught:
        run(own, config=config)
    assert [p.message for p in caught.value.problems] == [
        '`car.note("x")`: modifiers applied to the whole scenario are not supported by the runner'
    ]


def test_a_plugin_that_implements_a_runner_behaviour_is_refused(tmp_path):
    plugin = tmp_path / "clash.py"
    plugin.write_text(
        "from osc2check.plugins import modifier\n\n@modifier('speed')\nclass Speed:\n"
        "    def start(self, run, actor, **kw): pass\n",
        encoding="utf-8",
    )
    with pytest.raises(ScenarioError) as caught:
        run(GREETING, config=with_plugins(EXAMPLE_PLUGIN, str(plugin)))
    (problem,) = caught.value.problems
    assert "implements modifier `speed`, which the runner implements already" in problem.message


def test_two_plugins_that_implement_one_behaviour_are_a_configuration_error(tmp_path):
    copy = tmp_path / "again.py"
    copy.write_text(Path(EXAMPLE_PLUGIN).read_text(encoding="utf-8"), encoding="utf-8")
    with pytest.raises(ConfigError, match="action `log` is implemented twice"):
        with_plugins(EXAMPLE_PLUGIN, str(copy)).plugin_registry()


def test_osc2run_reads_plugin_and_the_configuration(tmp_path, capsys):
    out = tmp_path / "out"
    status = osc2run_main([str(GREETING), "--plugin", EXAMPLE_PLUGIN, "--out", str(out)])
    assert status == 0
    assert "Good Bye!" in (out / "events.csv").read_text(encoding="utf-8")
    # the same from [tool.osc2check] plugins, relative to the configuration file
    folder = tmp_path / "project"
    folder.mkdir()
    (folder / "greeting.osc").write_text(GREETING.read_text(encoding="utf-8"), encoding="utf-8")
    (folder / "driving.osc").write_text((EXAMPLES / "driving.osc").read_text(), encoding="utf-8")
    (folder / "plugins").mkdir()
    (folder / "plugins" / "example_plugin.py").write_text(Path(EXAMPLE_PLUGIN).read_text())
    (folder / "osc2check.toml").write_text('plugins = ["plugins/example_plugin.py"]\n')
    status = osc2run_main([str(folder / "greeting.osc"), "--out", str(tmp_path / "out2")])
    assert status == 0, capsys.readouterr().err
    # a plug-in that cannot be imported: said before anything runs
    status = osc2run_main([str(GREETING), "--plugin", "no_such_module_xyz", "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and "plug-in `no_such_module_xyz` cannot be imported" in err


def test_installed_distributions_offer_plugins_in_the_entry_point_group(monkeypatch, tmp_path):
    from importlib.metadata import EntryPoint

    (tmp_path / "installed_osc_plugin.py").write_text(Path(EXAMPLE_PLUGIN).read_text())
    monkeypatch.syspath_prepend(str(tmp_path))
    point = EntryPoint("example", "installed_osc_plugin", plugin_api.ENTRY_POINT_GROUP)
    monkeypatch.setattr(
        plugin_api,
        "entry_points",
        lambda group: [point] if group == plugin_api.ENTRY_POINT_GROUP else [],
    )
    monkeypatch.setattr(plugin_api, "_loaded", {})
    registry = plugin_api.load_plugins(())
    assert registry.modules == ["installed_osc_plugin"]
    result = run(GREETING, config=with_plugins())
    assert result.outcome.status == "success", result.outcome.reason


def test_a_keep_of_a_plugin_action_parameter_is_the_value_it_gets(own):
    config = with_plugins(str(own.parent / "my_plugin.py"))
    text = OWN_SCENARIO.replace(
        '        shout("fast!")\n',
        '        shout("fast!") with:\n            keep(it.times == 3)\n',
    )
    own.write_text(text, encoding="utf-8")
    result = run(own, config=config, duration=30)
    assert [r.detail for r in result.events if r.kind == "log" and r.name == "shout"] == [
        "fast!"
    ] * 3


# ---- scenario_execution's own files, with their libraries from the module map ------------

THIRD_PARTY = os.environ.get("OSC2_THIRD_PARTY")
needs_third_party = pytest.mark.skipif(
    not THIRD_PARTY or not (Path(THIRD_PARTY) / "scenario_execution").is_dir(),
    reason="OSC2_THIRD_PARTY does not name a folder with scenario_execution",
)


def scenario_execution(name: str) -> tuple[Path, object]:
    root = Path(THIRD_PARTY or "") / "scenario_execution"
    library = root / "scenario_execution" / "scenario_execution" / "lib_osc"
    modules = {f"osc.{m}": str(library / f"{m}.osc") for m in ("helpers", "types")}
    return root / name, config_from_mapping({"modules": modules, "plugins": [EXAMPLE_PLUGIN]})


@needs_third_party
def test_scenario_execution_hello_world_logs_through_the_example_plugin():
    path, config = scenario_execution("examples/example_scenario/hello_world.osc")
    result = run(path, config=config)
    assert result.outcome.status == "success", result.outcome.reason
    logs = [(r.time, r.detail) for r in result.events if r.kind == "log"]
    assert logs == [(0.0, "Hello World!"), (3.0, "Good Bye!")]  # wait elapsed(3s) between


@needs_third_party
def test_scenario_execution_test_log_logs_the_message_its_keep_chose():
    path, config = scenario_execution("scenario_execution_coverage/scenarios/test_log.osc")
    messages = set()
    for seed in range(4):
        result = run(path, config=config, seed=seed)
        assert result.outcome.status == "success", result.outcome.reason
        (message,) = [r.detail for r in result.events if r.kind == "log"]
        messages.add(message)
    assert messages <= {"foo", "bar"} and messages


def test_a_campaign_runs_its_plugins_in_each_run_and_replays_with_them(tmp_path):
    out = tmp_path / "campaign"
    argv = [str(GREETING), "--plugin", EXAMPLE_PLUGIN, "--runs", "2", "--jobs", "1"]
    assert osc2run_main([*argv, "--out", str(out), "-q"]) == 0
    document = json.loads((out / "campaign.json").read_text(encoding="utf-8"))
    assert "plugins" not in document["options"]  # code: never read back from a folder
    for run_json in document["runs"]:
        assert run_json["outcome"]["status"] == "success"
        assert run_json["replay"].endswith(f"--seed {run_json['seed']} --plugin={EXAMPLE_PLUGIN}")
        events = (out / run_json["folder"] / "events.csv").read_text(encoding="utf-8")
        assert "Hello World!" in events and "Good Bye!" in events
    # a folder is data: --resume imports only the plug-ins its command line names
    assert osc2run_main(["--resume", str(out), "-q"]) == 2
    assert osc2run_main(["--resume", str(out), "--plugin", EXAMPLE_PLUGIN, "-q"]) == 0


def test_osc2check_reads_plugin(capsys):
    from osc2check.cli import main as osc2check_main

    assert osc2check_main([str(GREETING)]) == 0
    assert capsys.readouterr().out.count("A308") == 3
    assert osc2check_main([str(GREETING), "--plugin", EXAMPLE_PLUGIN]) == 0
    assert "A308" not in capsys.readouterr().out
    assert osc2check_main([str(GREETING), "--plugin", "no_such_module_xyz"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("osc2check: error: plugins: plug-in `no_such_module_xyz` cannot be")
