"""The ``osc2check`` command: argv → Config → analyze → format → exit code.

No analysis happens here. Exit codes: 0 when no finding is at or above the
``--fail-on`` severity, 1 when one is, 2 for a usage, configuration or I/O
error or an internal error (with a message on stderr, never a traceback unless
``--debug``).

A path that cannot be read (missing, a broken or looping link, a FIFO, socket or
device, no permission, too large) is reported for itself, on stderr and in the
output format's place for it, and the other files are still checked and written;
the exit status is then 2. A special file met while walking a folder is skipped with
a note. ``osc2check.inputs`` reads the files, never blocking.
"""

from __future__ import annotations

import argparse
import logging
import os
import stat
import sys
import traceback
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TextIO

from osc2check import cache, codes, inputs
from osc2check.codes import Severity
from osc2check.config import (
    FORMAT_ALIASES,
    OUTPUT_FORMATS,
    Config,
    ConfigError,
    add_config_arguments,
    add_language_arguments,
    chosen_config,
    load_config,
    parse_codes,
    parse_severity,
    with_language_arguments,
)
from osc2check.inputs import InputError, InputProblem
from osc2check.memory import DEFAULT_MEMORY_LIMIT_MIB
from osc2check.output import render, render_statistics, tool
from osc2check.source import decode_source

if TYPE_CHECKING:  # imported where first needed, to keep the start fast
    from osc2check.analysis import Analysis, SourceInput
    from osc2check.diagnostics import Diagnostic
    from osc2check.verify.check import ScenarioResult

__all__ = ["EXIT_ERROR", "EXIT_FINDINGS", "EXIT_OK", "UsageError", "build_parser", "main"]

log = logging.getLogger(__name__)

EXIT_OK, EXIT_FINDINGS, EXIT_ERROR = 0, 1, 2
STDIN = "-"
STDIN_URI = "<stdin>"

_EPILOG = """\
commands:
  osc2check rule CODE   print the documentation of a code (N101 or undefined-name)
  osc2check rule        list every code

exit status:
  0  no finding at or above --fail-on (default: error)
  1  findings at or above --fail-on
  2  usage, configuration or I/O error, or an internal error; a file that cannot
     be read is reported for itself and every other file is still checked
  130  interrupted (Ctrl-C)

Configuration is read from the nearest osc2check.toml or pyproject.toml with a
[tool.osc2check] table, looking upward from the first path. Options given here
override it; --ignore adds to the configured ignore list.

environment:
  OSC2_RESIDENT=1     hand the check to a warm process of this toolkit, started by
                      the first such command (docs/performance.md)
  OSC2_RESIDENT_IDLE  seconds that process waits for a check before it exits (600)
  OSC2_CACHE_DIR      the start-up cache's folder; OSC2_NO_CACHE=1: no cache
"""


class UsageError(Exception):
    """A problem with the command line or the configuration (exit status 2)."""


class _ArgumentParser(argparse.ArgumentParser):
    """argparse that reports a bad command line as one line, ``osc2check: error: ...``."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(message)


class _Version(argparse.Action):
    """``--version``: the installed version, looked up only when asked for (the lookup
    imports ``importlib.metadata``, a good part of a small check's start-up)."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: Any) -> None:
        super().__init__(
            option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, nargs=0,
            help="show program's version number and exit",
        )  # fmt: skip

    def __call__(self, parser: argparse.ArgumentParser, *args: Any, **kwargs: Any) -> NoReturn:
        sys.stdout.write(f"{parser.prog} {tool.version()}\n")
        parser.exit()


def _mebibytes(text: str) -> int:
    """A memory budget in MiB: a non-negative integer (0: no budget)."""
    if not text.isdigit():
        raise argparse.ArgumentTypeError(f"expected a number of MiB, got {text!r}")
    return int(text)


def _seed(text: str) -> int:
    """A seed: a non-negative integer (``-1`` and ``1`` would draw the same witness)."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {text!r}")
    return value


@dataclass(frozen=True, slots=True)
class _Input:
    uri: str
    path: Path | None  # None for standard input


def build_parser() -> argparse.ArgumentParser:
    """The parser of the checking command (``osc2check [options] PATH...``)."""
    p = _ArgumentParser(
        prog="osc2check",
        description="Check ASAM OpenSCENARIO DSL 2.x (.osc) files.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "paths",
        nargs="*",
        metavar="PATH",
        help="files or folders (searched for *.osc); '-' reads standard input (default: .)",
    )
    p.add_argument("--stdin-filename", metavar="NAME", help="the file name to report for '-'")
    p.add_argument(
        "--output-format",
        choices=(*OUTPUT_FORMATS, *FORMAT_ALIASES),
        help="how to print findings (default: full)",
    )
    p.add_argument("--select", metavar="CODES", help="comma list of codes, names or prefixes")
    p.add_argument("--ignore", metavar="CODES", help="comma list of codes to leave out")
    p.add_argument("--strict", action="store_true", default=None, help="D warnings are errors")
    p.add_argument(
        "--fail-on",
        choices=("error", "warning", "info"),
        help="lowest severity that makes the exit status 1 (default: error)",
    )
    p.add_argument("--exit-zero", action="store_true", help="exit 0 even when there are findings")
    add_language_arguments(p)
    add_config_arguments(p)
    p.add_argument(
        "--statistics", action="store_true", help="print a count per code instead of findings"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="leave out the summary line")
    p.add_argument("--dump-ast", action="store_true", help="print the syntax tree of each file")
    p.add_argument(
        "--witness",
        action="store_true",
        help="also print, for each scenario whose constraints can hold, the concrete values "
        "of its parameters and every actor's start lane, position, heading and speed",
    )
    p.add_argument("--scenario", metavar="NAME", help="verify only the scenario NAME")
    p.add_argument(
        "--seed",
        type=_seed,
        default=0,
        metavar="N",
        help="pick the witness with seed N, a non-negative integer (default 0): different "
        "seeds, different witnesses",
    )
    p.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the start-up cache (the parser's tables, the analysed "
        "standard library and the results of checks repeated on unchanged files, kept in "
        "the user's cache folder or OSC2_CACHE_DIR)",
    )
    p.add_argument(
        "--memory-limit",
        type=_mebibytes,
        metavar="MIB",
        help="memory the check of one file may add, in MiB (default "
        f"{DEFAULT_MEMORY_LIMIT_MIB}; 0: no budget); past it the file is S003",
    )
    p.add_argument("--debug", action="store_true", help="log details; show tracebacks")
    p.add_argument("--version", action=_Version)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``) and return the exit status."""
    args = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args
    try:
        if args[:1] == ["rule"]:
            return _rule_command(args[1:], sys.stdout)
        if args[:1] == ["migrate"]:
            return _migrate_command(args[1:], sys.stdout)
        return _check_command(args, sys.stdout)
    except BrokenPipeError:  # the reader went away (`osc2check . | head`): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_FINDINGS
    except SystemExit as exc:  # argparse: --help, --version, bad options
        return exc.code if isinstance(exc.code, int) else EXIT_ERROR
    except (UsageError, ConfigError) as exc:
        sys.stderr.write(f"osc2check: error: {exc}\n")
        return EXIT_ERROR
    except Exception as exc:  # the one guard of this entry point
        if _interrupt_in_a_foreign_call(exc):
            raise KeyboardInterrupt from exc  # Ctrl-C: said as such by the caller
        if debug:
            traceback.print_exc(file=sys.stderr)
        sys.stderr.write(f"osc2check: internal error: {type(exc).__name__}: {exc}\n")
        if not debug:
            sys.stderr.write("osc2check: run with --debug to see the traceback\n")
        return EXIT_ERROR


def _interrupt_in_a_foreign_call(exc: Exception) -> bool:
    """Whether ``exc`` is a Ctrl-C that arrived while ctypes converted the arguments of a
    foreign call (z3's): ctypes reports it as ``ArgumentError: argument 1:
    KeyboardInterrupt``, without the interrupt itself."""
    import ctypes

    return isinstance(exc, ctypes.ArgumentError) and ": KeyboardInterrupt" in str(exc)


# --- osc2check rule ---------------------------------------------------------------


def _rule_command(argv: list[str], out: TextIO) -> int:
    p = _ArgumentParser(prog="osc2check rule", description="Print the documentation of a code.")
    p.add_argument("code", nargs="?", metavar="CODE", help="a code or name; none lists all")
    args = p.parse_args(argv)
    if args.code is None:
        for c in sorted(codes.ALL, key=lambda c: c.code):
            out.write(f"{c.code}  {c.slug:<28} {c.severity.label:<8} {c.summary}\n")
        return EXIT_OK
    code = codes.lookup(args.code)
    if code is None:
        raise UsageError(f"unknown code {args.code!r} (osc2check rule lists them)")
    from osc2check import rules

    out.write(rules.page_text(code))
    return EXIT_OK


# --- osc2check migrate ------------------------------------------------------------


def _migrate_command(argv: list[str], out: TextIO) -> int:
    p = _ArgumentParser(
        prog="osc2check migrate",
        description="Write files of CARLA scenario_runner's OSC2 dialect as standard OSC2 "
        "(what the toolkit reads them as). Each file's standard text goes to standard "
        "output, or with --out to a file of the same name in that folder; the forms "
        "rewritten are listed on standard error.",
    )
    p.add_argument("paths", nargs="+", metavar="FILE", help="the .osc files")
    p.add_argument("--out", metavar="DIR", help="write FILE's name in DIR instead of printing")
    p.add_argument(
        "--dialect",
        choices=("auto", "carla"),
        default="auto",
        help="carla: every file is CARLA's; auto (default): the files that import basic.osc",
    )
    args = p.parse_args(argv)
    from osc2check.dialects.migrate import migrate

    folder = Path(args.out) if args.out else None
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)
    status = EXIT_OK
    for name in args.paths:
        try:
            data = inputs.read_bytes(name)
        except InputError as exc:
            sys.stderr.write(f"osc2check: error: {name}: cannot read: {exc}\n")
            status = EXIT_ERROR
            continue
        text, _ = decode_source(data)
        migration = migrate(text, name, args.dialect)
        for form in migration.forms:
            sys.stderr.write(f"{name}:{form.span.line}:{form.span.column}: {form.code} rewritten\n")
        if folder is not None:
            (folder / Path(name).name).write_text(migration.text, encoding="utf-8")
        else:
            out.write(migration.text)
    return status


# --- checking ---------------------------------------------------------------------


def _check_command(argv: list[str], out: TextIO) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="osc2check: %(levelname)s: %(name)s: %(message)s",
        stream=sys.stderr,
    )
    if args.no_cache:
        cache.set_enabled(False)
    paths = args.paths or ["."]
    config = _with_options(_load_config(args, paths), args)
    # a plug-in named that cannot be loaded: said before anything runs; the installed ones
    # load when a file calls a behaviour only a plug-in can implement (docs/plugins.md)
    config.plugin_registry(installed=False)
    sources, problems = _read(_collect(paths, config, args.stdin_filename))
    _report_problems(problems, args.quiet)
    failed = any(p.is_error for p in problems)
    if args.dump_ast:
        status = _dump_ast(sources, out)
        return EXIT_ERROR if failed else status

    diagnostics: list[Diagnostic] = []
    results: list[ScenarioResult] = []
    texts = {s.uri: s.text for s in sources}
    unverified = 0  # constraints left out of a verdict: in the summary even when C411 is not shown
    if sources:
        # the scenarios' results are printed with a witness and in JSON only: a large file's
        # findings can then come group by group (osc2check.groups)
        by_groups = not args.witness and config.output_format != "json"
        seed = args.seed if args.witness else None
        analysis = _analyze(sources, config, seed, args.scenario, by_groups)
        failure = config.plugin_failure()
        if failure is not None:
            raise failure
        diagnostics = analysis.diagnostics
        results = [r for checked in analysis.verified.values() for r in checked.scenarios]
        unverified = len(analysis.unverified)
        texts.update(analysis.texts)
    summaries = []
    if results:
        from osc2check.verify.check import scenario_summary  # z3 loads only when needed

        summaries = [scenario_summary(r, args.witness) for r in results]
    if args.statistics:
        text = render_statistics(
            diagnostics,
            files_checked=len(sources),
            quiet=args.quiet,
            problems=problems,
            unverified=unverified,
        )
    else:
        text = render(
            config.output_format,
            diagnostics,
            texts,
            files_checked=len(sources),
            quiet=args.quiet,
            scenarios=summaries,
            problems=problems,
            unverified=unverified,
        )
        if args.witness and config.output_format not in ("json", "sarif", "github"):
            text += _witness_tables(results)
    out.write(text)
    out.flush()
    if failed:
        return EXIT_ERROR
    if args.exit_zero or not config.fails(diagnostics):
        return EXIT_OK
    return EXIT_FINDINGS


def _report_problems(problems: list[InputProblem], quiet: bool) -> None:
    """One stderr line per path not checked: errors always, notes unless ``quiet``."""
    for p in problems:
        if p.is_error:
            sys.stderr.write(f"osc2check: error: {p.path}: {p.message}\n")
        elif not quiet:
            sys.stderr.write(f"osc2check: note: {p.path}: {p.message}\n")
    sys.stderr.flush()


def _load_config(args: argparse.Namespace, paths: list[str]) -> Config:
    chosen = chosen_config(args)
    if chosen is not None:
        return chosen
    first = paths[0]
    if first == STDIN:
        start = Path(args.stdin_filename).parent if args.stdin_filename else Path.cwd()
    else:
        start = Path(first)
    try:
        if not start.is_dir():  # a file, or a path that cannot be read: its folder
            start = start.parent
        if not start.is_dir():
            start = Path.cwd()
    except OSError:
        start = Path.cwd()
    config, path = load_config(start)
    log.debug("configuration: %s", path or "defaults")
    return config


def _codes_option(value: str, option: str) -> frozenset[codes.Code]:
    names = [n.strip() for n in value.split(",") if n.strip()]
    return parse_codes(names, key=option)


def _with_options(config: Config, args: argparse.Namespace) -> Config:
    changes: dict[str, Any] = {}
    if args.select is not None:
        changes["select"] = _codes_option(args.select, "--select")
    if args.ignore is not None:
        changes["ignore"] = config.ignore | _codes_option(args.ignore, "--ignore")
    if args.strict:
        changes["strict"] = True
    if args.fail_on is not None:
        changes["fail_on"] = parse_severity(args.fail_on, key="--fail-on")
    if args.memory_limit is not None:
        changes["memory_limit_mib"] = args.memory_limit
    if args.output_format is not None:
        changes["output_format"] = FORMAT_ALIASES.get(args.output_format, args.output_format)
    return with_language_arguments(replace(config, **changes), args)


def _display(path: Path) -> str:
    """``path`` relative to the working directory when below it, with ``/``.

    Links are followed (a linked file is reported under its target's name, beside the
    files it imports); a link that cannot be followed is named as given.
    """
    try:
        real = path.resolve(strict=True)
    except (OSError, RuntimeError):  # broken or looping link: RuntimeError before 3.13
        return _display_as_given(path)
    try:
        return real.relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return path.as_posix()


def _display_as_given(path: Path) -> str:
    """``path`` relative to the working directory when below it, links not followed."""
    absolute = Path(os.path.abspath(path))
    try:
        return absolute.relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return path.as_posix()


def _excluded(config: Config, path: Path, *, name_only: bool = False) -> bool:
    """``config.is_excluded``; a looping link, which it cannot resolve, is not excluded."""
    try:
        return config.is_excluded(path, name_only=name_only)
    except RuntimeError:  # pathlib's "Symlink loop" (Python < 3.13): reported when read
        return False


def _cannot_read(path: Path, why: str) -> InputProblem:
    return InputProblem(_display_as_given(path), f"cannot read: {why}")


def _walk(root: Path, config: Config) -> tuple[list[Path], list[InputProblem]]:
    """The ``*.osc`` files below ``root``, and the paths below it that were not taken.

    A folder that cannot be listed and a ``.osc`` link that leads nowhere cannot be
    read (errors); a FIFO, socket or device named ``*.osc`` is skipped with a note.
    Links to folders are not followed.
    """
    check = not _excluded(config, root)  # a folder named explicitly is searched anyway
    found: list[Path] = []
    problems: list[InputProblem] = []
    for met in inputs.walk(root, lambda p: check and _excluded(config, p, name_only=True)):
        if met.why is None:
            found.append(met.path)
        elif met.error:
            problems.append(_cannot_read(met.path, met.why))
        else:
            problems.append(
                InputProblem(_display_as_given(met.path), f"skipped: {met.why}", Severity.INFO)
            )
    return found, problems


def _collect(
    paths: list[str], config: Config, stdin_filename: str | None
) -> list[_Input | InputProblem]:
    """The inputs named by ``paths`` (folders walked) and the paths that will not be
    checked, in the order met."""
    entries: list[_Input | InputProblem] = []
    seen: set[str] = set()
    for raw in paths:
        if raw == STDIN:
            uri = Path(stdin_filename).as_posix() if stdin_filename else STDIN_URI
            found: list[_Input | InputProblem] = [_Input(uri, None)]
        else:
            found = _named(Path(raw), config)
        for entry in found:
            key = entry.uri if isinstance(entry, _Input) else entry.path
            if key not in seen:
                seen.add(key)
                entries.append(entry)
    if not any(isinstance(e, _Input) or e.is_error for e in entries):
        skipped = len(entries)  # only special files, each skipped with a note
        also = f" ({skipped} skipped: not regular files)" if skipped else ""
        raise UsageError(f"no .osc files found in {', '.join(paths)}{also}")
    return entries


def _named(path: Path, config: Config) -> list[_Input | InputProblem]:
    """What one path on the command line stands for: a file, a folder's files, a problem."""
    excluded = config.force_exclude and _excluded(config, path)
    try:
        status = inputs.probe(path)
    except InputError as exc:
        return [] if excluded else [_cannot_read(path, str(exc))]
    if stat.S_ISDIR(status.st_mode):
        files, problems = _walk(path, config)
        entries: list[_Input | InputProblem] = [_Input(_display(p), p) for p in files]
        return sorted(
            [*entries, *problems],
            key=lambda e: e.uri if isinstance(e, _Input) else e.path,
        )
    if excluded:
        return []
    why = inputs.not_regular(status)
    if why is not None:
        return [_cannot_read(path, why)]
    return [_Input(_display(path), path)]


def _read(entries: list[_Input | InputProblem]) -> tuple[list[SourceInput], list[InputProblem]]:
    """The decoded sources, and the paths not checked (those met, then those unreadable).

    A file that is not valid UTF-8 is read, and carries its problem (P004).
    """
    from osc2check.analysis import SourceInput

    sources = []
    problems = []
    for entry in entries:
        if isinstance(entry, InputProblem):
            problems.append(entry)
            continue
        try:
            if entry.path is None:
                if sys.stdin is None:  # closed when the process started (<&-)
                    raise InputError("standard input is closed")
                data = inputs.read_stream(sys.stdin.buffer)
            else:
                data = inputs.read_bytes(entry.path)
        except InputError as exc:
            problems.append(InputProblem(entry.uri, f"cannot read: {exc}"))
            continue
        text, problem = decode_source(data)
        on_disk = entry.path is not None  # standard input is not kept
        sources.append(SourceInput(uri=entry.uri, text=text, problem=problem, on_disk=on_disk))
    return sources, problems


def _analyze(
    sources: list[SourceInput],
    config: Config,
    seed: int | None,
    scenario: str | None,
    by_groups: bool = False,
) -> Analysis:
    from osc2check.analysis import analyze

    options = config.analysis_options(seed=seed, scenario=scenario)
    return analyze(sources, replace(options, by_groups=by_groups))


def _witness_tables(results: list[ScenarioResult]) -> str:
    """The readable witness of every scenario, or why there is none."""
    parts = []
    for r in results:
        if r.invoked_by:
            by = ", ".join(f"`{name}`" for name in r.invoked_by)
            parts.append(
                f"no witness for scenario `{r.scenario.name}`: it is invoked by {by}, whose "
                "witness places its actors (`--scenario` checks it on its own)"
            )
        elif r.witness is not None:
            parts.append(r.witness.table())
        else:
            why = (
                "its constraints cannot all hold"
                if r.outcome.status == "unsat"
                else "the solver could not decide"
            )
            parts.append(f"no witness for scenario `{r.scenario.name}`: {why}")
    return ("\n" + "\n\n".join(parts) + "\n") if parts else ""


def _dump_ast(sources: list[SourceInput], out: TextIO) -> int:
    from osc2check.syntax import dump, parse  # provided by the parser

    for source in sources:
        if len(sources) > 1:
            out.write(f"==> {source.uri} <==\n")
        text = dump(parse(source.text, source.uri).ast)
        out.write(text if text.endswith("\n") else text + "\n")
    return EXIT_OK


def run() -> NoReturn:
    """The ``osc2check`` command (``osc2check.results.run``: a check repeated on unchanged
    inputs gives its stored result)."""
    from osc2check.results import run as run_command

    run_command()


if __name__ == "__main__":
    run()
