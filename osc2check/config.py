"""Configuration: ``[tool.osc2check]`` in ``pyproject.toml``, or ``osc2check.toml``.

``load_config(start_dir)`` looks upward from ``start_dir`` for the nearest
directory holding an ``osc2check.toml`` (its keys at top level) or a
``pyproject.toml`` with a ``[tool.osc2check]`` table; in one directory the
former wins. Keys are kebab-case (``fail-on``; ``fail_on`` is accepted too), and
an unknown key or a bad value raises ``ConfigError`` naming the file and key.

``Config.policy`` is the last step of an analysis: it applies select/ignore,
per-file ignores, severity overrides and ``strict``, then sorts.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from fnmatch import fnmatchcase
from pathlib import Path, PurePosixPath
from types import MappingProxyType
from typing import TYPE_CHECKING, Any
from urllib.parse import unquote, urlparse

from osc2check import codes
from osc2check.codes import Code, Severity
from osc2check.diagnostics import Diagnostic
from osc2check.inputs import InputError, is_file, not_regular, probe
from osc2check.memory import DEFAULT_MEMORY_LIMIT_MIB
from osc2check.plugins import PluginError, PluginRegistry, load_plugins
from osc2check.semantics.profile import DEFAULT_DIALECT, DEFAULT_OSC_VERSION, DIALECTS, OSC_VERSIONS

if TYPE_CHECKING:
    from osc2check.analysis import AnalysisOptions

__all__ = [
    "CONFIG_FILE",
    "DEFAULT_EXCLUDE",
    "OUTPUT_FORMATS",
    "Config",
    "ConfigError",
    "add_language_arguments",
    "config_from_mapping",
    "config_for",
    "find_config",
    "load_config",
    "load_config_file",
    "parse_codes",
    "parse_severity",
    "with_language_arguments",
]

CONFIG_FILE = "osc2check.toml"
OUTPUT_FORMATS = ("full", "concise", "json", "sarif", "github")
FORMAT_ALIASES = {"text": "full"}
DEFAULT_EXCLUDE = (
    ".git", ".hg", ".svn", ".venv", "venv", ".tox", ".nox", "node_modules",
    "build", "dist", "__pycache__", ".mypy_cache", ".ruff_cache", ".pytest_cache",
)  # fmt: skip

_ALL_CODES: frozenset[Code] = frozenset(codes.ALL)
_SECTION = "tool.osc2check"


class ConfigError(Exception):
    """A configuration that cannot be used; ``str()`` names the file and the key."""

    def __init__(self, message: str, path: Path | str | None = None, key: str | None = None):
        super().__init__(message)
        self.message = message
        self.path = Path(path) if path is not None else None
        self.key = key

    def __str__(self) -> str:
        where = [str(self.path)] if self.path is not None else []
        if self.key:
            where.append(self.key)
        return ": ".join([*where, self.message])


@dataclass(frozen=True)
class Config:
    """Settings of one run. ``root`` is the directory globs are relative to."""

    select: frozenset[Code] = _ALL_CODES
    ignore: frozenset[Code] = frozenset()
    strict: bool = False
    fail_on: Severity = Severity.ERROR
    output_format: str = "full"
    per_file_ignores: Mapping[str, frozenset[Code]] = field(default_factory=dict)
    severity_overrides: Mapping[Code, Severity] = field(default_factory=dict)
    exclude: tuple[str, ...] = ()
    force_exclude: bool = False
    road: Mapping[str, Any] = field(default_factory=dict)
    solver: Mapping[str, Any] = field(default_factory=dict)
    memory_limit_mib: int = DEFAULT_MEMORY_LIMIT_MIB  # per file checked; 0: no budget
    search_paths: tuple[str, ...] = ()  # folders for `import a.b` (a/b.osc), after the file's own
    modules: Mapping[str, str] = field(default_factory=dict)  # `import a.b` -> a file (absolute)
    maps: Mapping[str, str] = field(default_factory=dict)  # a map name -> an .xodr file (absolute)
    osc_version: str = DEFAULT_OSC_VERSION
    dialect: str = DEFAULT_DIALECT
    plugins: tuple[str, ...] = ()  # Python modules implementing behaviours of .osc libraries
    root: Path | None = None

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as plain data (a campaign sends it to its workers); its tables are
        read-only views, which pickle cannot take."""
        values = {
            f.name: dict(v) if isinstance(v := getattr(self, f.name), MappingProxyType) else v
            for f in fields(self)
        }
        return (_config_of, (values,))

    def analysis_options(self, **changes: Any) -> AnalysisOptions:
        """The options ``analyze`` runs with under this configuration (``changes`` on top)."""
        from osc2check.analysis import AnalysisOptions

        road_map = self.road.get("map", "default")
        options = AnalysisOptions(
            search_paths=self.search_paths,
            modules=self.modules,
            maps=self.maps,
            osc_version=self.osc_version,
            dialect=self.dialect,
            default_map=str(road_map),
            solver_rlimit=_int_or_none(self.solver.get("rlimit")),
            solver_timeout_ms=_int_or_none(self.solver.get("timeout-ms")),
            memory_limit_mib=self.memory_limit_mib or None,
            policy=self.policy,
            plugins=self.plugins,
        )
        return replace(options, **changes)

    def plugin_registry(self, *, installed: bool = True) -> PluginRegistry:
        """The plug-ins this configuration names (and the installed ones), loaded; a
        ``ConfigError`` when one cannot be, said before anything is analysed.
        ``installed=False``: the installed ones are left to load when the registry is
        first asked (``plugin_failure`` then says whether one could not be)."""
        try:
            registry = load_plugins(self.plugins)
            if installed:
                registry.load_installed()
        except PluginError as exc:
            raise ConfigError(str(exc), None, "plugins") from None
        return registry

    def plugin_failure(self) -> ConfigError | None:
        """The installed plug-in that could not be loaded when the registry was asked
        (None when it was not asked, or all loaded)."""
        failure = load_plugins(self.plugins).failure
        return ConfigError(str(failure), None, "plugins") if failure is not None else None

    def enabled(self, code: Code) -> bool:
        """True when ``code`` is selected and not ignored."""
        return code in self.select and code not in self.ignore

    def ignored_in_file(self, code: Code, uri: str) -> bool:
        """True when a ``per-file-ignores`` pattern matching ``uri`` lists ``code``."""
        if not self.per_file_ignores:
            return False
        rel = self._relative(uri)
        return any(
            code in ignored and _glob_match(rel, pattern)
            for pattern, ignored in self.per_file_ignores.items()
        )

    def is_excluded(self, path: str | Path, *, name_only: bool = False) -> bool:
        """True when ``path`` matches a built-in or configured ``exclude`` pattern.

        A pattern without ``/`` matches any component of the path, or with
        ``name_only`` only its last one (for a directory walk that prunes as it
        descends, so that a directory named on the command line is never
        excluded by its own name).
        """
        rel = self._relative(str(path))
        return any(
            _glob_match(rel, p, any_component=not name_only)
            for p in (*DEFAULT_EXCLUDE, *self.exclude)
        )

    def severity_of(self, diagnostic: Diagnostic) -> Severity:
        """The severity after overrides; ``strict`` turns every D code into an error."""
        severity = self.severity_overrides.get(diagnostic.code, diagnostic.severity)
        if self.strict and diagnostic.code.family == "D":
            return Severity.ERROR
        return severity

    def policy(self, diagnostics: Iterable[Diagnostic], uri: str | None = None) -> list[Diagnostic]:
        """Filter and re-grade ``diagnostics`` by this configuration, sorted by ``sort_key``.

        ``uri`` is the file the per-file ignores are matched against; ``None``
        means each diagnostic's own ``span.uri``.
        """
        kept = []
        for d in diagnostics:
            if not self.enabled(d.code) or self.ignored_in_file(d.code, uri or d.span.uri):
                continue
            severity = self.severity_of(d)
            kept.append(d if severity == d.severity else replace(d, severity=severity))
        return sorted(kept, key=lambda d: d.sort_key)

    def fails(self, diagnostics: Iterable[Diagnostic]) -> bool:
        """True when some diagnostic is at or above the ``fail_on`` severity."""
        return any(d.severity <= self.fail_on for d in diagnostics)

    def _relative(self, uri: str) -> str:
        path = _uri_path(uri)
        base = self.root or Path.cwd()
        try:
            return Path(path).resolve().relative_to(base.resolve()).as_posix()
        except (ValueError, OSError, RuntimeError):  # RuntimeError: a symlink loop (< 3.13)
            return PurePosixPath(Path(path).as_posix()).as_posix()


def _config_of(values: dict[str, Any]) -> Config:
    """A pickled ``Config`` again (see ``Config.__reduce__``)."""
    tables: dict[str, Any] = {
        k: MappingProxyType(v) if isinstance(v, dict) else v for k, v in values.items()
    }
    return Config(**tables)


def _int_or_none(value: object) -> int | None:
    return value if isinstance(value, int) else None


def _uri_path(uri: str) -> str:
    if uri.startswith("file://"):
        return unquote(urlparse(uri).path)
    return uri


def _glob_match(rel: str, pattern: str, *, any_component: bool = True) -> bool:
    """Match a ``/``-separated relative path against a glob.

    A pattern without ``/`` matches a path component (a file or directory name:
    any one, or the last with ``any_component=False``); a pattern naming a
    directory matches everything below it.
    """
    pat = pattern.strip().rstrip("/")
    if pat.startswith("./"):
        pat = pat[2:]
    if not pat:
        return False
    if "/" not in pat:
        parts = rel.split("/") if any_component else rel.split("/")[-1:]
        return any(fnmatchcase(part, pat) for part in parts)
    candidates = [pat, pat + "/*"]
    if pat.startswith("**/"):
        candidates += [pat[3:], pat[3:] + "/*"]
    return any(fnmatchcase(rel, c) for c in candidates)


# --- reading ------------------------------------------------------------------


def parse_codes(
    patterns: Iterable[str], *, path: Path | str | None = None, key: str | None = None
) -> frozenset[Code]:
    """Codes named by codes, slugs or prefixes (``N``, ``N1``, ``N101``, ``ALL``).

    Every pattern must name at least one code, else ``ConfigError``.
    """
    chosen: set[Code] = set()
    for pattern in patterns:
        if not isinstance(pattern, str):
            raise ConfigError(f"expected a code, got {pattern!r}", path, key)
        found = codes.select([pattern]) if pattern.strip() else set()
        if not found:
            raise ConfigError(f"unknown code, name or prefix {pattern!r}", path, key)
        chosen |= found
    return frozenset(chosen)


def parse_severity(
    value: object, *, path: Path | str | None = None, key: str | None = None
) -> Severity:
    """``"error"``, ``"warning"`` or ``"info"`` (any case) as a ``Severity``."""
    names = {s.label: s for s in Severity}
    if isinstance(value, str) and value.lower() in names:
        return names[value.lower()]
    raise ConfigError(f"expected one of {', '.join(map(repr, names))}, got {value!r}", path, key)


# Where a value was read: the configuration file, if any (ConfigError names it).
_Where = Path | str | None
# Reads the value of one key into the Config fields it sets.
_Reader = Callable[[object, _Where, str], dict[str, Any]]


def _expect(
    value: object, kind: type | tuple[type, ...], what: str, path: _Where, key: str | None
) -> Any:  # `value` itself, of the type `kind` (TOML data)
    if not isinstance(value, kind) or (kind is not bool and isinstance(value, bool)):
        raise ConfigError(f"expected {what}, got {value!r}", path, key)
    return value


def _string_list(value: object, path: _Where, key: str) -> list[str]:
    items: list[object] = _expect(value, list, "a list of strings", path, key)
    return [_expect(item, str, "a list of strings", path, key) for item in items]


def _read_select(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"select": parse_codes(_string_list(v, path, key), path=path, key=key)}


def _read_ignore(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"ignore": parse_codes(_string_list(v, path, key), path=path, key=key)}


def _read_strict(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"strict": _expect(v, bool, "true or false", path, key)}


def _read_force_exclude(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"force_exclude": _expect(v, bool, "true or false", path, key)}


def _read_fail_on(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"fail_on": parse_severity(v, path=path, key=key)}


def _read_output_format(v: object, path: _Where, key: str) -> dict[str, Any]:
    name = FORMAT_ALIASES.get(str(v), v)
    if name not in OUTPUT_FORMATS:
        choices = ", ".join(map(repr, OUTPUT_FORMATS))
        raise ConfigError(f"expected one of {choices}, got {v!r}", path, key)
    return {"output_format": name}


def _read_per_file_ignores(v: object, path: _Where, key: str) -> dict[str, Any]:
    table = _expect(v, dict, 'a table of glob = ["CODE", ...]', path, key)
    result: dict[str, frozenset[Code]] = {}
    for pattern, names in table.items():
        sub = f'{key}."{pattern}"'
        result[pattern] = parse_codes(_string_list(names, path, sub), path=path, key=sub)
    return {"per_file_ignores": MappingProxyType(result)}


def _read_severity(v: object, path: _Where, key: str) -> dict[str, Any]:
    table = _expect(v, dict, 'a table of CODE = "error" | "warning" | "info"', path, key)
    result: dict[Code, Severity] = {}
    for name, level in table.items():
        sub = f"{key}.{name}"
        severity = parse_severity(level, path=path, key=sub)
        for code in parse_codes([name], path=path, key=sub):
            result[code] = severity
    return {"severity_overrides": MappingProxyType(result)}


def _read_exclude(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"exclude": tuple(_string_list(v, path, key))}


def _raw_table(name: str) -> _Reader:
    def read(v: object, path: _Where, key: str) -> dict[str, Any]:
        return {name: MappingProxyType(dict(_expect(v, dict, "a table", path, key)))}

    return read


def _read_solver(v: object, path: _Where, key: str) -> dict[str, Any]:
    table = dict(_expect(v, dict, "a table", path, key))
    for name in ("rlimit", "timeout-ms"):
        value = table.get(name)
        if value is not None and (
            not isinstance(value, int) or isinstance(value, bool) or value <= 0
        ):
            raise ConfigError(f"expected a positive integer, got {value!r}", path, f"{key}.{name}")
    return {"solver": MappingProxyType(table)}


def _read_memory_limit(v: object, path: _Where, key: str) -> dict[str, Any]:
    if not isinstance(v, int) or isinstance(v, bool) or v < 0:
        raise ConfigError(f"expected a number of MiB (0: no budget), got {v!r}", path, key)
    return {"memory_limit_mib": v}


def _base(path: _Where) -> Path:
    """The folder relative paths in the configuration are taken from: the file's."""
    return Path(path).resolve().parent if path else Path.cwd()


def _read_search_paths(v: object, path: _Where, key: str) -> dict[str, Any]:
    return {"search_paths": tuple(str(_base(path) / p) for p in _string_list(v, path, key))}


def _file_table(name: str, what: str) -> _Reader:
    """A table of names to files, relative to the configuration file (made absolute)."""

    def read(v: object, path: _Where, key: str) -> dict[str, Any]:
        table = _expect(v, dict, f'a table of {what} = "path"', path, key)
        files = {}
        for entry, file in table.items():
            files[entry] = str(_base(path) / _expect(file, str, "a path", path, f"{key}.{entry}"))
        return {name: MappingProxyType(files)}

    return read


def _choice(name: str, choices: tuple[str, ...]) -> _Reader:
    def read(v: object, path: _Where, key: str) -> dict[str, Any]:
        if not isinstance(v, str) or v not in choices:
            expected = ", ".join(f'"{c}"' for c in choices)
            raise ConfigError(f"expected one of {expected}, got {v!r}", path, key)
        return {name: v}

    return read


def _read_plugins(v: object, path: _Where, key: str) -> dict[str, Any]:
    """Modules by name, or ``.py`` files relative to the configuration file."""
    names = _string_list(v, path, key)
    return {"plugins": tuple(str(_base(path) / n) if n.endswith(".py") else n for n in names)}


_READERS: dict[str, _Reader] = {
    "select": _read_select,
    "ignore": _read_ignore,
    "strict": _read_strict,
    "fail-on": _read_fail_on,
    "output-format": _read_output_format,
    "per-file-ignores": _read_per_file_ignores,
    "severity": _read_severity,
    "exclude": _read_exclude,
    "force-exclude": _read_force_exclude,
    "road": _raw_table("road"),
    "solver": _read_solver,
    "search-paths": _read_search_paths,
    "memory-limit": _read_memory_limit,
    "modules": _file_table("modules", "module"),
    "maps": _file_table("maps", "map name"),
    "osc-version": _choice("osc_version", OSC_VERSIONS),
    "dialect": _choice("dialect", DIALECTS),
    "plugins": _read_plugins,
}


def config_from_mapping(
    data: Mapping[str, Any],
    *,
    path: Path | str | None = None,
    root: Path | None = None,
    prefix: str = "",
) -> Config:
    """A ``Config`` from the keys of one TOML table (``prefix`` names the table in errors)."""
    values: dict[str, Any] = {}
    for raw_key, value in data.items():
        name = raw_key.replace("_", "-")
        key = f"{prefix}{raw_key}"
        reader = _READERS.get(name)
        if reader is None:
            import difflib

            close = difflib.get_close_matches(name, _READERS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise ConfigError(f"unknown key{hint}", path, key)
        values.update(reader(value, path, key))
    return Config(root=root, **values)


def _read_toml(path: Path) -> dict[str, Any]:
    import tomllib  # only where a configuration file is found

    try:
        with path.open("rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"invalid TOML: {exc}", path) from None
    except OSError as exc:
        raise ConfigError(f"cannot read: {exc.strerror or exc}", path) from None


def _tool_table(data: Mapping[str, Any], path: Path) -> Mapping[str, Any] | None:
    tool = data.get("tool")
    if not isinstance(tool, dict) or "osc2check" not in tool:
        return None
    table = tool["osc2check"]
    if not isinstance(table, dict):
        raise ConfigError("expected a table", path, _SECTION)
    return table


def load_config_file(path: str | Path) -> Config:
    """The configuration in one file: a ``pyproject.toml`` or an ``osc2check.toml``."""
    path = Path(path)
    data = _read_toml(path)
    root = path.resolve().parent
    table = _tool_table(data, path)
    if table is not None:
        return config_from_mapping(table, path=path, root=root, prefix=f"{_SECTION}.")
    if path.name == "pyproject.toml":
        raise ConfigError(f"no [{_SECTION}] table", path)
    return config_from_mapping(data, path=path, root=root)


def find_config(start_dir: str | Path) -> Path | None:
    """The nearest ``osc2check.toml`` or ``pyproject.toml`` with our table, looking upward."""
    start = Path(start_dir).resolve()
    if start.is_file():
        start = start.parent
    for directory in (start, *start.parents):
        own = directory / CONFIG_FILE
        if is_file(own):
            return own
        pyproject = directory / "pyproject.toml"
        if (
            is_file(pyproject)
            and _mentions_us(pyproject)
            and _tool_table(_read_toml(pyproject), pyproject) is not None
        ):
            return pyproject
    return None


def _mentions_us(path: Path) -> bool:
    """Whether a ``pyproject.toml`` can hold our table at all: most do not even name us,
    and are then not parsed (reading TOML is a good part of a small check's start-up)."""
    try:
        return b"osc2check" in path.read_bytes()
    except OSError:
        return True  # reading it again says why it cannot be read


def load_config(start_dir: str | Path) -> tuple[Config, Path | None]:
    """The configuration that applies to ``start_dir`` and the file it came from.

    Without a configuration file, the defaults (and ``None``).
    """
    path = find_config(start_dir)
    if path is None:
        return Config(), None
    return load_config_file(path), path


def config_for(scenario: str | Path) -> Config:
    """The configuration that applies to a scenario file: the nearest above its folder
    (what ``osc2check FILE`` reads; ``osc2run`` and ``osc2lsp`` read the same)."""
    config, _ = load_config(Path(scenario).resolve().parent)
    return config


# --- which configuration: --config FILE, --isolated (osc2check, osc2run) ------------


def add_config_arguments(parser: Any) -> None:
    """``--config FILE`` and ``--isolated`` on an ``argparse`` parser (osc2check,
    osc2run): the same configuration for the checker and the runner."""
    parser.add_argument("--config", metavar="FILE", help="read the configuration from FILE")
    parser.add_argument("--isolated", action="store_true", help="ignore configuration files")


def chosen_config(args: Any) -> Config | None:
    """The configuration ``--config FILE`` names (a FIFO or a folder is refused before it
    is opened, so it cannot block), ``Config()`` with ``--isolated``, else None: the
    nearest one above the file applies."""
    if args.config:
        try:
            why = not_regular(probe(args.config))
        except InputError:
            why = None  # the loader says why it cannot read it
        if why:
            raise ConfigError(f"cannot read: {why}", args.config)
        return load_config_file(args.config)
    if args.isolated:
        return Config()
    return None


# --- the language options, the same in every command -------------------------------


def add_language_arguments(parser: Any) -> None:
    """``--osc-version``, ``--dialect`` and ``--plugin`` on an ``argparse`` parser
    (osc2check, osc2run)."""
    parser.add_argument(
        "--osc-version",
        choices=OSC_VERSIONS,
        help=f"the OSC2 version whose standard library is used (default {DEFAULT_OSC_VERSION}, "
        "or osc-version in [tool.osc2check])",
    )
    parser.add_argument(
        "--dialect",
        choices=DIALECTS,
        help="how other tools' forms are read: carla reads CARLA scenario_runner's; auto "
        "(the default) does when a file imports CARLA's basic.osc",
    )
    parser.add_argument(
        "--plugin",
        action="append",
        metavar="MODULE",
        help="a Python module (or .py file) implementing actions, modifiers or methods of "
        "your .osc libraries (docs/plugins.md); repeatable, added to plugins in "
        "[tool.osc2check]",
    )


def with_language_arguments(config: Config, args: Any) -> Config:
    """``config`` with the ``--osc-version``, ``--dialect`` and ``--plugin`` given on the
    command line."""
    changes: dict[str, Any] = {
        name: value
        for name in ("osc_version", "dialect")
        if (value := getattr(args, name, None)) is not None
    }
    if getattr(args, "plugin", None):
        changes["plugins"] = (*config.plugins, *args.plugin)
    return replace(config, **changes) if changes else config
