"""The installed plug-ins (entry point group ``osc2toolkit.plugins``) as the checker loads
them: when a file first calls a behaviour only a plug-in can implement, not at start-up;
one that cannot be imported is said then, as a configuration error (docs/plugins.md)."""

from __future__ import annotations

from importlib.metadata import EntryPoint
from pathlib import Path

import pytest

from osc2check import plugins as plugin_api
from osc2check.cli import main as osc2check_main
from osc2check.config import ConfigError, config_from_mapping

ROOT = Path(__file__).parents[2]
EXAMPLE_PLUGIN = ROOT / "examples" / "plugins" / "example_plugin.py"
GREETING = ROOT / "examples" / "plugins" / "greeting.osc"  # calls log and accelerate_to
PLAIN = ROOT / "examples" / "cut_in_and_stop.osc"  # calls the standard library only


@pytest.fixture
def installed(monkeypatch, tmp_path):
    """Install the plug-in modules named (entry points of the group), for this test."""
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(plugin_api, "_loaded", {})
    scans: list[str] = []

    def install(*modules: str) -> list[str]:
        points = [EntryPoint(m, m, plugin_api.ENTRY_POINT_GROUP) for m in modules]

        def entry_points(group: str) -> list[EntryPoint]:
            scans.append(group)
            return points if group == plugin_api.ENTRY_POINT_GROUP else []

        monkeypatch.setattr(plugin_api, "entry_points", entry_points)
        return scans

    (tmp_path / "installed_greeting_plugin.py").write_text(EXAMPLE_PLUGIN.read_text())
    return install


def test_an_installed_plugin_implements_the_calls_of_a_file(installed, capsys):
    installed("installed_greeting_plugin")
    assert osc2check_main([str(GREETING), "--isolated"]) == 0
    assert "A308" not in capsys.readouterr().out


def test_the_installed_plugins_are_looked_up_only_for_a_call_only_a_plugin_implements(
    installed, capsys
):
    scans = installed("no_such_installed_plugin_xyz")
    assert osc2check_main([str(PLAIN), "--isolated"]) == 0
    assert "All checks passed" in capsys.readouterr().out
    assert scans == []


def test_a_broken_installed_plugin_is_a_configuration_error_when_a_file_needs_it(installed, capsys):
    installed("installed_greeting_plugin", "no_such_installed_plugin_xyz")
    assert osc2check_main([str(GREETING), "--isolated"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith(
        "osc2check: error: plugins: plug-in `no_such_installed_plugin_xyz` cannot be imported"
    )


def test_the_runner_and_the_server_load_the_installed_plugins_before_anything_runs(installed):
    scans = installed("no_such_installed_plugin_xyz")
    config = config_from_mapping({"plugins": [str(EXAMPLE_PLUGIN)]})
    with pytest.raises(ConfigError, match="no_such_installed_plugin_xyz` cannot be imported"):
        config.plugin_registry()
    assert scans == [plugin_api.ENTRY_POINT_GROUP]
    # the named plug-in's calls stay implemented; the failure is kept, the scan not redone
    registry = config.plugin_registry(installed=False)
    assert registry.find("action", [None], "log") is not None
    assert str(config.plugin_failure()).endswith(
        "cannot be imported: ModuleNotFoundError: No module named 'no_such_installed_plugin_xyz'"
    )
    assert scans == [plugin_api.ENTRY_POINT_GROUP]
