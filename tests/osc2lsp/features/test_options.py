"""Settings from the client."""

from __future__ import annotations

from osc2check.codes import Severity
from osc2check.config import Config
from osc2lsp.options import CheckerConfigs, InlayHintOptions, Options, apply_options, from_settings


def test_settings_nested_dotted_and_camel_case():
    options, problems = from_settings(
        {
            "osc2": {
                "strict": True,
                "select": ["N"],
                "inlayHints": {"enabled": True},
                "diagnostics": {"debounce": 40},
            }
        }
    )
    assert problems == []
    assert options == Options(
        strict=True, select=("N",), debounce=40, inlay_hints=InlayHintOptions(enabled=True)
    )
    dotted, _ = from_settings({"osc2.inlayHints.parameterNames": False})
    assert dotted.inlay_hints.parameter_names is False


def test_bad_settings_are_reported_and_ignored():
    options, problems = from_settings(
        {"osc2": {"strict": "yes", "ignore": ["X999"], "diagnostics": {"debounce": -1}}}
    )
    assert options == Options()
    assert len(problems) == 3 and "osc2.strict" in problems[0]


def test_client_options_apply_over_the_file_configuration(tmp_path):
    (tmp_path / "pyproject.toml").write_text(
        '[tool.osc2check]\nignore = ["D803"]\nstrict = true\n', encoding="utf-8"
    )
    configs = CheckerConfigs()
    config = configs.for_file(str(tmp_path / "a.osc"), Options(ignore=("N104",)))
    assert config.strict and {c.code for c in config.ignore} == {"D803", "N104"}
    relaxed = configs.for_file(str(tmp_path / "a.osc"), Options(strict=False))
    assert not relaxed.strict


def test_apply_options_without_changes_keeps_the_configuration():
    config = Config(fail_on=Severity.WARNING)
    assert apply_options(config, Options()) is config
