"""Configuration: discovery, reading, errors, and the policy applied to findings."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check import codes
from osc2check.codes import Severity
from osc2check.config import (
    Config,
    ConfigError,
    config_from_mapping,
    find_config,
    load_config,
    load_config_file,
)
from osc2check.diagnostics import Diagnostic
from osc2check.source import Span


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def diag(code: codes.Code, uri: str = "a.osc", line: int = 1, column: int = 1) -> Diagnostic:
    return Diagnostic(code, "m", Span(uri, line, column, line, column + 1), code.severity)


def test_defaults_select_every_code_and_fail_on_errors():
    config = Config()
    assert all(config.enabled(c) for c in codes.ALL)
    assert config.fail_on is Severity.ERROR
    assert config.output_format == "full"
    assert not config.strict


def test_load_config_without_any_file_gives_defaults(tmp_path):
    assert load_config(tmp_path) == (Config(), None)


def test_pyproject_table_is_found_from_a_nested_folder(tmp_path):
    pyproject = write(
        tmp_path / "pyproject.toml",
        """\
[project]
name = "x"

[tool.osc2check]
select = ["N", "T2"]
ignore = ["undefined-name"]
strict = true
fail-on = "warning"
output-format = "concise"
per-file-ignores = { "legacy/*.osc" = ["D8"] }
severity = { N107 = "error" }
exclude = ["generated"]

[tool.osc2check.road]
lanes = 3
lane-width = "3.5m"

[tool.osc2check.solver]
rlimit = 5000000
""",
    )
    nested = tmp_path / "scenarios" / "highway"
    nested.mkdir(parents=True)
    config, path = load_config(nested)
    assert path == pyproject
    assert codes.UNKNOWN_MEMBER in config.select and codes.DIMENSION_MISMATCH in config.select
    assert codes.SYNTAX_ERROR not in config.select
    assert config.ignore == {codes.UNDEFINED_NAME}
    assert config.strict and config.fail_on is Severity.WARNING
    assert config.output_format == "concise"
    assert config.per_file_ignores["legacy/*.osc"] == codes.select(["D8"])
    assert config.severity_overrides == {codes.IMPORT_CYCLE: Severity.ERROR}
    assert config.exclude == ("generated",)
    assert dict(config.road) == {"lanes": 3, "lane-width": "3.5m"}
    assert dict(config.solver) == {"rlimit": 5000000}
    assert config.root == tmp_path.resolve()


def test_pyproject_without_our_table_is_skipped(tmp_path):
    outer = write(tmp_path / "pyproject.toml", '[tool.osc2check]\nfail-on = "info"\n')
    write(tmp_path / "inner" / "pyproject.toml", '[project]\nname = "inner"\n')
    config, path = load_config(tmp_path / "inner")
    assert path == outer
    assert config.fail_on is Severity.INFO


def test_osc2check_toml_wins_over_pyproject_in_the_same_folder(tmp_path):
    write(tmp_path / "pyproject.toml", '[tool.osc2check]\nfail-on = "info"\n')
    own = write(tmp_path / "osc2check.toml", 'fail-on = "warning"\n')
    assert find_config(tmp_path) == own
    assert load_config(tmp_path)[0].fail_on is Severity.WARNING


def test_nearest_config_wins(tmp_path):
    write(tmp_path / "osc2check.toml", "strict = true\n")
    inner = write(tmp_path / "a" / "osc2check.toml", "strict = false\n")
    config, path = load_config(tmp_path / "a" / "b.osc")
    assert path == inner
    assert not config.strict


def test_snake_case_keys_and_text_alias_are_accepted():
    config = config_from_mapping({"fail_on": "warning", "output_format": "text"})
    assert config.fail_on is Severity.WARNING
    assert config.output_format == "full"


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ('fail-on = "fatal"', "tool.osc2check.fail-on: expected one of 'error'"),
        ('select = ["X99"]', "tool.osc2check.select: unknown code, name or prefix 'X99'"),
        ("select = 3", "tool.osc2check.select: expected a list of strings, got 3"),
        ('strict = "yes"', "tool.osc2check.strict: expected true or false"),
        ("fial-on = 1", "tool.osc2check.fial-on: unknown key; did you mean 'fail-on'?"),
        ('output-format = "xml"', "tool.osc2check.output-format: expected one of 'full'"),
        ('severity = { N101 = "fatal" }', "tool.osc2check.severity.N101: expected one of"),
        ('per-file-ignores = { "a/*.osc" = ["Q1"] }', 'per-file-ignores."a/*.osc": unknown code'),
        ('road = "straight"', "tool.osc2check.road: expected a table"),
    ],
)
def test_bad_values_name_file_and_key(tmp_path, text, fragment):
    path = write(tmp_path / "pyproject.toml", f"[tool.osc2check]\n{text}\n")
    with pytest.raises(ConfigError) as info:
        load_config(tmp_path)
    assert str(info.value).startswith(f"{path}: ")
    assert fragment in str(info.value)
    assert info.value.path == path


def test_invalid_toml_is_a_config_error(tmp_path):
    path = write(tmp_path / "osc2check.toml", "select = [\n")
    with pytest.raises(ConfigError, match="invalid TOML") as info:
        load_config(tmp_path)
    assert info.value.path == path


def test_explicit_pyproject_without_table_is_an_error(tmp_path):
    path = write(tmp_path / "pyproject.toml", '[project]\nname = "x"\n')
    with pytest.raises(ConfigError, match=r"no \[tool.osc2check\] table"):
        load_config_file(path)


def test_missing_explicit_file_is_an_error(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        load_config_file(tmp_path / "nope.toml")


def test_policy_filters_by_select_and_ignore_and_sorts():
    config = Config(select=codes.select(["N", "D"]), ignore=codes.select(["N102"]))
    given = [
        diag(codes.UNITLESS_PHYSICAL_LITERAL, line=5),
        diag(codes.DIMENSION_MISMATCH, line=1),
        diag(codes.DUPLICATE_DEFINITION, line=2),
        diag(codes.UNDEFINED_NAME, line=3),
    ]
    kept = config.policy(given, "a.osc")
    assert [d.code.code for d in kept] == ["N101", "D805"]


def test_policy_applies_per_file_ignores_relative_to_the_config_root(tmp_path):
    config = Config(
        per_file_ignores={"legacy/*.osc": codes.select(["D"]), "*_gen.osc": codes.select(["N"])},
        root=tmp_path,
    )
    legacy = str(tmp_path / "legacy" / "old.osc")
    d805 = diag(codes.UNITLESS_PHYSICAL_LITERAL, legacy)
    n101 = diag(codes.UNDEFINED_NAME, legacy)
    assert config.policy([d805, n101], legacy) == [n101]
    generated = str(tmp_path / "deep" / "x_gen.osc")
    assert config.policy([diag(codes.UNDEFINED_NAME, generated)]) == []
    other = str(tmp_path / "new.osc")
    assert len(config.policy([diag(codes.UNITLESS_PHYSICAL_LITERAL, other)])) == 1


def test_policy_strict_makes_d_codes_errors_and_overrides_change_severity():
    config = Config(strict=True, severity_overrides={codes.UNDEFINED_NAME: Severity.WARNING})
    d805, n101, t204 = (
        diag(codes.UNITLESS_PHYSICAL_LITERAL, line=1),
        diag(codes.UNDEFINED_NAME, line=2),
        diag(codes.FLOAT_TO_INT, line=3),
    )
    kept = config.policy([t204, n101, d805])
    assert [(d.code.code, d.severity) for d in kept] == [
        ("D805", Severity.ERROR),
        ("N101", Severity.WARNING),
        ("T204", Severity.WARNING),
    ]
    assert Config().policy([d805])[0].severity is Severity.WARNING


def test_strict_wins_over_a_severity_override_of_a_d_code():
    config = Config(strict=True, severity_overrides={codes.USE_STATEMENT: Severity.INFO})
    assert config.policy([diag(codes.USE_STATEMENT)])[0].severity is Severity.ERROR


def test_fails_compares_with_fail_on():
    warning = diag(codes.FLOAT_TO_INT)
    assert not Config().fails([warning])
    assert Config(fail_on=Severity.WARNING).fails([warning])
    assert Config(fail_on=Severity.INFO).fails([warning])
    assert not Config(fail_on=Severity.INFO).fails([])


def test_exclude_matches_default_folders_and_configured_globs(tmp_path):
    config = Config(exclude=("generated", "scenarios/legacy", "*_tmp.osc"), root=tmp_path)
    assert config.is_excluded(tmp_path / ".git" / "a.osc")
    assert config.is_excluded(tmp_path / "x" / "generated" / "a.osc")
    assert config.is_excluded(tmp_path / "scenarios" / "legacy" / "a.osc")
    assert config.is_excluded(tmp_path / "b_tmp.osc")
    assert not config.is_excluded(tmp_path / "scenarios" / "a.osc")
    # name_only looks at the last component only (a walk prunes as it descends)
    assert not config.is_excluded(tmp_path / "build" / "a.osc", name_only=True)
    assert config.is_excluded(tmp_path / "build", name_only=True)
