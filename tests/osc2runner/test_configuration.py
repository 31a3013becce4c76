"""One configuration for all three tools: `osc2run` reads `[tool.osc2check]` as
`osc2check` does (the OSC2 version, the default map, map names, the findings'
policy), next to the scenario file or above it; `--osc-version` and `--dialect`
override it as they do for the checker."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from osc2check.config import Config, load_config_file
from osc2runner.cli import main
from osc2runner.runner import check_file

ROOT = Path(__file__).resolve().parents[2]

VAN = """\
import osc.standard

scenario top:
    delivery: vehicle with:
        keep(it.vehicle_category == vehicle_category!van)
    do delivery.drive(duration: 2s) with:
        speed(30kph)
"""

NAMED_MAP = """\
import osc.standard

scenario top:
    town: map with:
        keep(it.map_file == "Town77")
    car: vehicle
    do car.drive(duration: 2s) with:
        speed(30kph)
"""

PLAIN = """\
import osc.standard

scenario top:
    car: vehicle
    do car.drive(duration: 2s) with:
        speed(30kph)
"""


def scenario(folder: Path, text: str, config: str | None = None) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    if config is not None:
        (folder / "osc2check.toml").write_text(config, encoding="utf-8")
    path = folder / "s.osc"
    path.write_text(text, encoding="utf-8")
    return path


def run_json(out: Path) -> dict:
    return json.loads((out / "run.json").read_text(encoding="utf-8"))


def test_the_version_comes_from_the_configuration_above_the_scenario(tmp_path, capsys):
    path = scenario(tmp_path / "scenarios" / "nested", VAN)
    assert main([str(path), "-q"]) == 2  # 2.1: `van` is no member
    assert "N106" in capsys.readouterr().err
    (tmp_path / "osc2check.toml").write_text('osc-version = "2.2"\n', encoding="utf-8")
    assert main([str(path), "--out", str(tmp_path / "out"), "-q"]) == 0
    assert run_json(tmp_path / "out")["actors"]["delivery"]["category"] == "van"


def test_the_command_line_overrides_the_configured_version(tmp_path, capsys):
    path = scenario(tmp_path, VAN, 'osc-version = "2.1"\n')
    assert main([str(path), "-q", "--osc-version", "2.2"]) == 0
    capsys.readouterr()


def test_the_configured_default_map_and_map_names_are_the_runners(tmp_path, capsys):
    path = scenario(tmp_path / "a", PLAIN, '[road]\nmap = "highway_4lane"\n')
    assert main([str(path), "--out", str(tmp_path / "out-a"), "-q"]) == 0
    assert run_json(tmp_path / "out-a")["map"]["name"] == "highway_4lane"
    folder = tmp_path / "b"
    (folder / "roads").mkdir(parents=True)
    shutil.copy(ROOT / "examples" / "maps" / "rural_curves.xodr", folder / "roads" / "r.xodr")
    path = scenario(folder, NAMED_MAP, '[maps]\nTown77 = "roads/r.xodr"\n')
    assert main([str(path), "--out", str(tmp_path / "out-b"), "-q"]) == 0
    source = run_json(tmp_path / "out-b")["map"]["source"]
    assert Path(source) == (folder / "roads" / "r.xodr").resolve()
    capsys.readouterr()


def test_a_bad_configuration_is_one_line_and_exit_2(tmp_path, capsys):
    path = scenario(tmp_path, PLAIN, "osc-version = 2.2\n")
    assert main([str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("osc2run: error: ") and "osc-version" in err
    assert len(err.splitlines()) == 1


def test_the_python_api_takes_a_configuration_or_reads_the_files(tmp_path):
    path = scenario(tmp_path, VAN, 'osc-version = "2.2"\n')
    assert check_file(path).analysis.programs[str(path)].library.version == "2.2"
    checked = check_file(path, config=Config(osc_version="2.2", dialect="standard"))
    assert checked.analysis.programs[str(path)].library.key == "2.2/standard"
    assert load_config_file(tmp_path / "osc2check.toml").osc_version == "2.2"


HELPERS = """\
import osc.standard

global cruise_speed: speed = 30kph
"""

WITH_HELPERS = """\
import osc.standard
import osc.helpers

scenario top:
    car: vehicle
    do car.drive(duration: 2s) with:
        speed(cruise_speed)
"""


def test_config_names_the_checkers_configuration_as_for_osc2check(tmp_path, capsys):
    """scenario_execution's users map `osc.<name>` to their libraries: a scenario checked
    with `osc2check --config FILE` runs with `osc2run --config FILE` (the runner had no
    such option, and refused the file the checker passed: N105)."""
    from osc2check.cli import main as check

    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "anything.osc").write_text(HELPERS, encoding="utf-8")
    conf = tmp_path / "conf" / "modules.toml"
    conf.parent.mkdir()
    conf.write_text('[modules]\n"osc.helpers" = "../lib/anything.osc"\n', encoding="utf-8")
    path = scenario(tmp_path / "scenarios", WITH_HELPERS)
    assert check([str(path), "--config", str(conf), "-q"]) == 0
    assert main([str(path), "--config", str(conf), "--out", str(tmp_path / "out"), "-q"]) == 0
    assert run_json(tmp_path / "out")["outcome"]["status"] == "success"
    capsys.readouterr()
    assert main([str(path), "-q"]) == 2  # without it, as the checker without it
    assert "N105" in capsys.readouterr().err
    missing = tmp_path / "missing.toml"
    assert main([str(path), "--config", str(missing)]) == 2
    assert (
        capsys.readouterr().err
        == f"osc2run: error: {missing}: cannot read: No such file or directory\n"
    )


def test_isolated_ignores_the_configuration_above_the_scenario(tmp_path, capsys):
    path = scenario(tmp_path, VAN, 'osc-version = "2.2"\n')
    assert main([str(path), "-q"]) == 0
    assert main([str(path), "-q", "--isolated"]) == 2  # 2.1: `van` is no member
    assert "N106" in capsys.readouterr().err
    path = scenario(tmp_path / "sut", PLAIN)
    (tmp_path / "sut" / "pyproject.toml").write_text(
        '[tool.osc2run]\nsut = "missing.py:Nobody"\n', encoding="utf-8"
    )
    assert main([str(path), "-q"]) == 2  # the configured system under test
    assert "--sut" in capsys.readouterr().err
    assert main([str(path), "-q", "--isolated"]) == 0  # no configuration file at all
