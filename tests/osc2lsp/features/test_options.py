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


def test_the_plugins_of_the_configuration_are_the_servers_too(tmp_path):
    """[tool.osc2check] plugins: the server's checker knows what they implement (no A308),
    and one that cannot be loaded is a configuration problem said once."""
    from pathlib import Path

    from osc2lsp.session.analysis import analyse

    examples = Path(__file__).parents[3] / "examples" / "plugins"
    for name in ("greeting.osc", "driving.osc", "example_plugin.py"):
        (tmp_path / name).write_text((examples / name).read_text(encoding="utf-8"))
    greeting = tmp_path / "greeting.osc"
    text = greeting.read_text(encoding="utf-8")

    def a308(config: Config) -> list[int]:
        snapshot = analyse([(greeting.as_uri(), text, 1)], config)[greeting.as_uri()]
        return [d.span.line for d in snapshot.analysis.diagnostics if d.code.code == "A308"]

    configs = CheckerConfigs()
    assert a308(configs.for_file(str(greeting), Options())) == [15, 19, 20]
    (tmp_path / "osc2check.toml").write_text('plugins = ["example_plugin.py"]\n')
    assert a308(configs.for_file(str(greeting), Options())) == []
    assert configs.problems == []
    (tmp_path / "osc2check.toml").write_text('plugins = ["no_such_plugin_xyz"]\n')
    configs = CheckerConfigs()
    assert a308(configs.for_file(str(greeting), Options())) == [15, 19, 20]
    assert configs.problems == [
        "plugins: plug-in `no_such_plugin_xyz` cannot be imported: "
        "ModuleNotFoundError: No module named 'no_such_plugin_xyz'"
    ]
