"""Settings of the server: defaulted dataclasses filled from the client's settings.

The client sends them as ``initializationOptions`` and in
``workspace/didChangeConfiguration`` (or answers ``workspace/configuration``
for the section ``osc2``). Keys may be camelCase or snake_case, nested or
dotted::

    {"osc2": {"strict": true, "select": ["N", "T"], "ignore": ["D803"],
              "inlayHints": {"enabled": true, "values": true, "parameterNames": true},
              "diagnostics": {"debounce": 100, "verifyDelay": 500, "previewAfter": 50},
              "verify": true}}

A bad value is reported (``from_settings`` returns the problems) and the
default is kept. The checker's own configuration (``[tool.osc2check]`` in
``pyproject.toml`` or ``osc2check.toml``) is read for each file's folder;
the client's ``strict``, ``select`` and ``ignore`` are applied on top.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from osc2check.config import Config, ConfigError, find_config, load_config_file, parse_codes

log = logging.getLogger(__name__)

SECTION = "osc2"


@dataclass(frozen=True)
class InlayHintOptions:
    enabled: bool = False
    values: bool = True  # folded values of physical expressions
    parameter_names: bool = True  # names of positional arguments


@dataclass(frozen=True)
class Options:
    strict: bool | None = None  # None: as [tool.osc2check] says
    select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()
    inlay_hints: InlayHintOptions = field(default_factory=InlayHintOptions)
    debounce: int = 100  # milliseconds between the last edit and the analysis
    verify: bool = True  # run the solver's checks (constraints, placement, flow)
    verify_delay: int = 500  # milliseconds of quiet before the solver runs
    # Publish a syntax-first preview of each edit of a document whose last analysis
    # took at least this many milliseconds (0: always; the analysis follows).
    preview_after: int = 50
    completion_limit: int = 200
    docs_url: str = ""  # where docs/checks.md is published; default: the local file


def _snake(name: str) -> str:
    return re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name).lower()


def _normalise(settings: Any) -> dict[str, Any]:
    """Nested snake_case keys from nested or dotted camelCase ones."""
    if not isinstance(settings, dict):
        return {}
    if SECTION in settings and isinstance(settings[SECTION], dict):
        settings = settings[SECTION]
    result: dict[str, Any] = {}
    for key, value in settings.items():
        parts = [_snake(p) for p in str(key).split(".")]
        if parts and parts[0] == SECTION:
            parts = parts[1:]
        target = result
        for part in parts[:-1]:
            target = target.setdefault(part, {})
        if not parts:
            continue
        if isinstance(value, dict):
            target.setdefault(parts[-1], {}).update(_normalise(value))
        else:
            target[parts[-1]] = value
    return result


def from_settings(settings: Any, base: Options | None = None) -> tuple[Options, list[str]]:
    """Options from client settings (unknown keys are ignored); returns the problems too."""
    base = base or Options()
    data = _normalise(settings)
    problems: list[str] = []
    values: dict[str, Any] = {}

    def take(
        key: str,
        kind: Any,
        check: Callable[[Any], str | None] | None = None,
        target: dict[str, Any] = values,
        source: dict[str, Any] = data,
        name: str | None = None,
    ) -> None:
        if key not in source:
            return
        value = source[key]
        if value is None:
            return
        if (
            kind is bool
            and not isinstance(value, bool)
            or kind is int
            and (not isinstance(value, int) or isinstance(value, bool))
        ):
            problems.append(
                f"setting `{SECTION}.{name or key}`: expected {kind.__name__}, got {value!r}"
            )
            return
        if kind is tuple:
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                problems.append(f"setting `{SECTION}.{name or key}`: expected a list of codes")
                return
            value = tuple(value)
        if check is not None:
            problem = check(value)
            if problem:
                problems.append(f"setting `{SECTION}.{name or key}`: {problem}")
                return
        target[key] = value

    def codes_ok(value: Any) -> str | None:
        try:
            parse_codes(value)
        except ConfigError as exc:
            return exc.message
        return None

    take("strict", bool)
    take("verify", bool)
    take("select", tuple, codes_ok)
    take("ignore", tuple, codes_ok)
    take("completion_limit", int)
    if isinstance(data.get("docs_url"), str):
        values["docs_url"] = data["docs_url"]
    diagnostics = data.get("diagnostics")
    if isinstance(diagnostics, dict):
        take(
            "debounce",
            int,
            lambda v: None if 0 <= v <= 5000 else "out of range",
            source=diagnostics,
            name="diagnostics.debounce",
        )
        take(
            "verify_delay",
            int,
            lambda v: None if 0 <= v <= 60000 else "out of range",
            source=diagnostics,
            name="diagnostics.verifyDelay",
        )
        take(
            "preview_after",
            int,
            lambda v: None if v >= 0 else "out of range",
            source=diagnostics,
            name="diagnostics.previewAfter",
        )
    hints = data.get("inlay_hints")
    if isinstance(hints, dict):
        hint_values: dict[str, Any] = {}
        for f in fields(InlayHintOptions):
            take(f.name, bool, target=hint_values, source=hints, name=f"inlayHints.{f.name}")
        values["inlay_hints"] = replace(base.inlay_hints, **hint_values)
    return replace(base, **values), problems


# ---- the checker's configuration --------------------------------------------------


class CheckerConfigs:
    """``[tool.osc2check]`` for each folder (re-read when its file changes), with the
    client's settings applied on top."""

    def __init__(self) -> None:
        self._found: dict[str, tuple[Path | None, float, Config]] = {}
        self.problems: list[str] = []

    def for_file(self, key: str, options: Options, root: str | None = None) -> Config:
        folder = str(Path(key).parent) if Path(key).is_absolute() else (root or str(Path.cwd()))
        config = self._load(folder)
        return apply_options(config, options)

    def _load(self, folder: str) -> Config:
        cached = self._found.get(folder)
        try:
            path = find_config(folder)
        except ConfigError as exc:
            self._problem(str(exc))
            return Config()
        mtime = path.stat().st_mtime if path is not None else 0.0
        if cached is not None and cached[0] == path and cached[1] == mtime:
            return cached[2]
        config = Config()
        if path is not None:
            try:
                config = load_config_file(path)
                config.plugin_registry()  # a plug-in that cannot be loaded: said once
            except ConfigError as exc:
                self._problem(str(exc))
        self._found[folder] = (path, mtime, config)
        return config

    def _problem(self, message: str) -> None:
        log.warning("configuration: %s", message)
        if message not in self.problems:
            self.problems.append(message)


def apply_options(config: Config, options: Options) -> Config:
    changes: dict[str, Any] = {}
    if options.strict is not None:
        changes["strict"] = options.strict
    if options.select:
        changes["select"] = parse_codes(options.select)
    if options.ignore:
        changes["ignore"] = config.ignore | parse_codes(options.ignore)
    return replace(config, **changes) if changes else config
