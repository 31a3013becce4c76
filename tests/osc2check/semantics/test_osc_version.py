"""DSL 2.2: its library beside 2.1's, chosen by `osc-version` or `--osc-version`.

The default stays 2.1. Under 2.2 the harmonised enumerations have 2.2's members
(with the 2.1 names as aliases), the movement modifiers their range parameters,
and the catalogue a row for every road vehicle category.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.cli import main
from osc2check.config import Config, ConfigError, config_from_mapping, load_config_file
from osc2check.semantics.profile import LibraryChoice
from osc2check.semantics.stdlib import standard_library
from osc2check.semantics.symbols import SymbolKind
from osc2check.verify.api import solve

VAN = """\
import osc.standard

scenario top:
    delivery: vehicle with:
        keep(it.vehicle_category == vehicle_category!van)
    do delivery.drive(duration: 5s) with:
        speed(30kph)
"""


def codes_of(text: str, **options: str) -> list[str]:
    analysis = analyze([SourceInput("t.osc", text)], AnalysisOptions(**options))  # type: ignore[arg-type]
    return [d.code.code for d in analysis.diagnostics]


def enum_members(version: str, enum: str) -> dict[str, int]:
    model = standard_library(version).model
    (sym,) = [s for s in model.symbols if s.kind is SymbolKind.ENUM and s.name == enum]
    return {m.name: m.value for m in model.enum_values(sym)}


def modifier_parameters(version: str, name: str) -> list[str]:
    model = standard_library(version).model
    (sym,) = [s for s in model.symbols if s.kind is SymbolKind.MODIFIER and s.name == name]
    return [p.name for p in model.all_members(sym) if p.kind is SymbolKind.FIELD]


def test_both_libraries_load_without_a_finding():
    assert standard_library("2.1").diagnostics == ()
    assert standard_library("2.2").diagnostics == ()


def test_the_default_is_2_1_and_a_2_2_member_is_not_in_it():
    assert Config().osc_version == "2.1" == AnalysisOptions().osc_version
    assert "N106" in codes_of(VAN)
    assert "N106" not in codes_of(VAN, osc_version="2.2")


def test_2_2_keeps_the_2_1_names_as_aliases_with_the_same_values():
    v21, v22 = enum_members("2.1", "vehicle_category"), enum_members("2.2", "vehicle_category")
    assert set(v21) < set(v22)
    assert all(v22[name] == value for name, value in v21.items())
    assert v22["heavy_truck"] == v22["truck"]
    assert v22["micro_mobility_device"] == v22["vru_vehicle"]
    assert v22["van"] == 6 and v22["land_vehicle"] == 18
    roles = enum_members("2.2", "traffic_participant_role")
    assert roles["fire_brigade"] == roles["fire"] and roles["freight_transport"] == 10
    assert "center_to_center" in enum_members("2.2", "lat_measure_by")


def test_2_2_modifiers_keep_their_2_1_parameters_and_gain_the_range_ones():
    v21, v22 = modifier_parameters("2.1", "speed"), modifier_parameters("2.2", "speed")
    assert v22[: len(v21)] == v21  # positional arguments bind as in 2.1
    assert v22[len(v21) :] == ["speed_range", "direction"]
    assert "distance_range" in modifier_parameters("2.2", "position")
    assert "speed_range" not in v21


def test_aliases_compare_equal_in_constraints():
    text = VAN.replace("vehicle_category!van", "heavy_truck and it.vehicle_category == truck")
    assert codes_of(text, osc_version="2.2") == ["L506"]


def test_a_van_is_placed_with_the_van_row():
    analysis = analyze([SourceInput("t.osc", VAN)], AnalysisOptions(osc_version="2.2"))
    witness = solve(analysis, "top")
    (delivery,) = witness.actors
    assert (delivery.category, float(delivery.length)) == ("van", 5.3)


def test_a_category_without_a_road_body_is_a_conflict():
    text = VAN.replace("vehicle_category!van", "aircraft")
    found = codes_of(text, osc_version="2.2")
    assert "C401" in found


def test_configuration_and_command_line_choose_the_version(tmp_path: Path, capsys):
    scenario = tmp_path / "van.osc"
    scenario.write_text(VAN, encoding="utf-8")
    assert main([str(scenario), "--output-format", "concise"]) == 1
    assert main([str(scenario), "--osc-version", "2.2"]) == 0
    (tmp_path / "osc2check.toml").write_text('osc-version = "2.2"\n', encoding="utf-8")
    assert main([str(scenario)]) == 0
    assert main([str(scenario), "--osc-version", "2.1"]) == 1
    capsys.readouterr()


def test_a_bad_version_names_the_key(tmp_path: Path):
    path = tmp_path / "osc2check.toml"
    path.write_text('osc-version = "3.0"\n', encoding="utf-8")
    with pytest.raises(ConfigError, match="osc-version"):
        load_config_file(path)
    with pytest.raises(ConfigError, match="dialect"):
        config_from_mapping({"dialect": "foretify"})


def test_the_library_choice_is_one_key_with_version_and_dialect():
    assert LibraryChoice().key == "2.1/auto"
    assert AnalysisOptions(osc_version="2.2", dialect="carla").library.key == "2.2/carla"
    with pytest.raises(ValueError):
        LibraryChoice("2.0")
