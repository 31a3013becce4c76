"""``analyze(sources, options)``: parse, resolve and check a set of files.

Each input file is checked as the root of its own program (the file, what it
imports, and the standard library), so a file's findings never depend on
which other files were given. Parsed files are shared between programs.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING

from osc2check import cache, codes, groups, memory, messages, results
from osc2check.diagnostics import Diagnostic, Severity
from osc2check.dialects import dialect_reading, may_read_as_carla
from osc2check.gc_pause import gc_paused
from osc2check.inputs import InputError, read_bytes
from osc2check.memory import DEFAULT_MEMORY_LIMIT_MIB
from osc2check.plugins import PluginError, PluginRegistry, load_plugins
from osc2check.semantics.profile import DEFAULT_DIALECT, DEFAULT_OSC_VERSION, LibraryChoice
from osc2check.semantics.program import Program, build_program
from osc2check.source import Span, decode_source, point_span, without_nul
from osc2check.suppress import Suppression, apply_suppressions, find_suppressions
from osc2check.syntax import ParseResult, parse
from osc2check.syntax.lexer import Comment
from osc2check.syntax.parser import Segment, assemble, parse_part
from osc2check.verify.flow import check_flow, scenarios_of

if TYPE_CHECKING:
    from osc2check.verify.check import VerifyResult

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class SourceInput:
    """A file to check: its name as reported, and its text.

    ``parse`` is the parse of ``text`` when the caller has one (the language server
    splices the re-parsed segments of an edit into its last parse,
    ``syntax.incremental.splice``); it is used instead of parsing again when its
    name and text are the input's. ``on_disk``: the text is the file as saved (not an
    editor's buffer), so a large one's parse is kept in the start-up cache as an
    imported file's is (``IMPORT_CACHE_SIZE``): checking it again reads it, and an
    edited version is parsed again only where it changed.
    """

    uri: str
    text: str
    problem: str | None = None  # why the file's bytes were not clean UTF-8 (P004)
    parse: ParseResult | None = None
    on_disk: bool = False


@dataclass
class Analysis:
    diagnostics: list[Diagnostic]
    texts: dict[str, str]
    programs: dict[str, Program] = field(default_factory=dict)
    parses: dict[str, ParseResult] = field(default_factory=dict)
    verified: dict[str, VerifyResult] = field(default_factory=dict)  # by root file
    options: AnalysisOptions | None = None  # what the files were analysed with
    # the constraints the solver left out of a verdict (C411, shown or not): span, reason
    unverified: set[tuple[Span, str]] = field(default_factory=set)


class FileCache:
    """Parse results by path, each as its dialect reads it (``osc2check.dialects``);
    sources given in memory win over the disk."""

    def __init__(
        self,
        sources: dict[str, str],
        parses: Mapping[str, ParseResult] | None = None,
        dialect: str = DEFAULT_DIALECT,
        saved: frozenset[str] = frozenset(),
    ):
        self.sources = sources
        self.saved = saved  # sources that are files as saved: their parse may be kept
        self.given = dict(parses or {})
        self.parses: dict[str, ParseResult] = {}
        self.dialect = dialect

    def read(self, uri: str) -> ParseResult | None:
        if uri in self.parses:
            return self.parses[uri]
        result = self.given.get(uri)
        if result is None:
            text = self.sources.get(uri)
            if text is None:
                try:
                    data = read_bytes(uri)  # never blocks, never reads past the size cap
                except InputError:
                    return None
                # An imported file's own findings (P004 included) show when it is checked.
                text, _ = decode_source(data)
                result = _parse_saved(text, uri)
            elif uri in self.saved:
                result = _parse_saved(text, uri)
            else:
                result = parse(text, uri)
        # a parse from the start-up cache is the file as written: its dialect reads it too
        result = dialect_reading(result, self.dialect)
        self.parses[uri] = result
        return result


#: a file read from disk at least this long (characters) has its parse kept in the
#: start-up cache (about 500 lines; smaller ones parse as fast as they load)
IMPORT_CACHE_SIZE = 20_000


def _parse_saved(text: str, uri: str) -> ParseResult:
    """The parse of a file read from disk; a large one made from the parse of its last
    version checked, kept in the start-up cache under its name: that parse itself when
    the file is unchanged (a library file a project imports, a file checked again),
    else with only the region where the two versions differ parsed again
    (``incremental.parse_from``, which gives what ``parse`` gives)."""
    if len(text) < IMPORT_CACHE_SIZE:
        return parse(text, uri)
    kind, key = "parse-" + cache.digest(uri)[:16], {"uri": uri}
    previous = cache.load(kind, key)
    result = None
    if isinstance(previous, ParseResult) and previous.uri == uri:
        from osc2check.syntax.incremental import parse_from

        result = parse_from(previous, text)
    if result is None:
        result = parse(text, uri)
    if result is not previous:
        cache.store(kind, key, result, keep=2)  # two toolkits sharing a cache folder
    return result


@dataclass(frozen=True)
class AnalysisOptions:
    """What ``analyze`` does, and with what settings; every field has its default.

    ``seed`` picks the witness among the many that satisfy a scenario (the same seed
    always gives the same one; None takes the solver's first model, the cheapest);
    ``scenario`` limits verification to one scenario; ``verify=False`` leaves out the
    solver (constraints, placement, timing), as editors do between keystrokes; the
    behaviour flow's checks (B codes that need no solver) run either way.
    ``implicit_imports`` are standard modules every file imports without saying so;
    ``modules`` maps structured import names to files; ``search_paths`` are the
    folders ``import a.b`` looks in after the importing file's own; ``maps`` names
    map files by the names scenarios give (``Town04`` -> an ``.xodr`` path).
    ``osc_version`` chooses the standard library (2.1 or 2.2) and ``dialect`` how
    other tools' forms are read (:mod:`osc2check.semantics.profile`). ``policy``
    filters and re-grades one file's diagnostics (``Config.policy``). ``plugins``
    are the plug-in modules (:mod:`osc2check.plugins`) whose implementations run
    behaviours of the user's libraries. ``memory_limit_mib`` is the memory the check
    of one file may add to the process (``memory.budget``; None for no budget, as the
    language server's own process has: its solver worker has one); past it the file
    has a single finding, S003.
    """

    verify: bool = True
    seed: int | None = None
    scenario: str | None = None
    implicit_imports: tuple[str, ...] = ()
    modules: Mapping[str, str] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    maps: Mapping[str, str] = field(default_factory=dict)
    osc_version: str = DEFAULT_OSC_VERSION
    dialect: str = DEFAULT_DIALECT
    default_map: str = "default"
    solver_rlimit: int | None = None
    solver_timeout_ms: int | None = None
    memory_limit_mib: int | None = DEFAULT_MEMORY_LIMIT_MIB
    policy: Callable[[list[Diagnostic], str], list[Diagnostic]] | None = None
    plugins: tuple[str, ...] = ()
    by_groups: bool = False

    @property
    def library(self) -> LibraryChoice:
        """The standard library these options build programs on."""
        return LibraryChoice(self.osc_version, self.dialect)


def analyze(sources: list[SourceInput], options: AnalysisOptions | None = None) -> Analysis:
    """Check every source; returns the diagnostics (options' policy applied) and the texts."""
    options = options if options is not None else AnalysisOptions()
    with gc_paused():  # analysis builds long-lived tables; collections only cost time
        return _analyze(sources, options)


def _plugins(names: tuple[str, ...]) -> PluginRegistry:
    """The plug-ins' registry; empty when one cannot be loaded (the command lines say why
    before they analyse: ``Config.plugin_registry``), so their behaviours are A308."""
    try:
        return load_plugins(names)
    except PluginError:
        return PluginRegistry()


def _analyze(sources: list[SourceInput], options: AnalysisOptions) -> Analysis:
    sources = [_clean(s) for s in sources]
    texts = {s.uri: s.text for s in sources}
    given = {
        s.uri: s.parse
        for s in sources
        if s.parse is not None and s.parse.uri == s.uri and s.parse.text == s.text
    }
    saved = frozenset(s.uri for s in sources if s.on_disk)
    cache = FileCache(texts, given, options.dialect, saved)
    modules = dict(options.modules)
    plugins = _plugins(options.plugins) if options.verify else None
    verified: dict[str, VerifyResult] = {}
    programs: dict[str, Program] = {}
    found: list[Diagnostic] = []
    unverified: set[tuple[Span, str]] = set()
    comments: dict[str, list[tuple[Span, str]]] = {}
    if options.memory_limit_mib:
        _load_once(options)
    for source in sources:
        start = point_span(source.uri, source.text, 0)
        try:
            with memory.budget(options.memory_limit_mib):
                grouped = _by_groups(source, cache, modules, plugins, options, programs, verified)
                if grouped is not None:
                    found += grouped.before + grouped.after
                    unverified |= grouped.unverified
                    comments[source.uri] = grouped.comments
                    continue
                _check_one(source, cache, modules, plugins, options, found, programs, verified)
        except Exception as exc:  # the budget was hit: say where, check the next file
            if not memory.is_out_of_memory(exc):
                raise
            results.not_repeatable("a memory budget was exceeded")
            element = (
                exc.element
                if isinstance(exc, memory.BudgetExceeded)
                else memory.Element(start, "checking the file")
            )
            # the finding is the checked file's, at the element when it is in that file
            span = element.span if element.span.uri == source.uri else start
            found.append(messages.memory_budget(span, element, options.memory_limit_mib))
    for checked in verified.values():
        unverified |= checked.unverified()
    diagnostics = _finish(found, cache, comments, texts, options)
    return Analysis(diagnostics, texts, programs, cache.parses, verified, options, unverified)


def _by_groups(
    source: SourceInput,
    cache: FileCache,
    modules: dict[str, str],
    plugins: PluginRegistry | None,
    options: AnalysisOptions,
    programs: dict[str, Program],
    verified: dict[str, VerifyResult],
) -> groups.Outcome | None:
    """A large file's findings group by group (:mod:`osc2check.groups`), or None when it
    is checked whole. When it is checked whole all the same (most of its groups changed),
    ``programs`` and ``verified`` have its program and results."""
    if not (
        options.by_groups
        and source.on_disk
        and source.problem is None
        and options.scenario is None
        and len(source.text) >= groups.MIN_SIZE
        and not may_read_as_carla(source.text, options.dialect)
    ):
        return None

    def check_part(
        text: str, chunks: list[groups.Chunk], numbers: dict[int, int]
    ) -> groups.Outcome | None:
        return _check_part(source.uri, text, chunks, numbers, cache, modules, plugins, options)

    def check_whole(numbers: dict[int, int]) -> tuple[groups.Outcome, bool]:
        found: list[Diagnostic] = []
        done = _check_one(source, cache, modules, plugins, options, found, programs, verified)
        parsed = cache.parses.get(source.uri)
        outcome = _outcome(source.uri, found, done, verified, parsed)
        return outcome, _stands(source.uri, found, done, parsed, programs.get(source.uri), numbers)

    return groups.check(source.uri, source.text, _options_key(options), check_part, check_whole)


def _options_key(options: AnalysisOptions) -> str:
    """What a file's findings depend on among the options: all but the policy, applied
    after (and ``by_groups`` itself)."""
    chosen = {f.name: getattr(options, f.name) for f in fields(options)}
    del chosen["policy"], chosen["by_groups"]
    return repr(
        sorted((k, sorted(v.items()) if isinstance(v, Mapping) else v) for k, v in chosen.items())
    )


def _check_part(
    uri: str,
    text: str,
    chunks: list[groups.Chunk],
    numbers: dict[int, int],
    cache: FileCache,
    modules: dict[str, str],
    plugins: PluginRegistry | None,
    options: AnalysisOptions,
) -> groups.Outcome | None:
    """The check of the file ``uri`` with only ``chunks`` (``text``: the other lines
    blank), as their group's outcome; None when it cannot stand for it (``_stands``)."""
    segments: list[Segment] = []
    comments: list[Comment] = []
    for run in _runs(chunks):
        lines = parse_part(text, uri, run[0], run[1], run[2])
        segments += lines.segments
        comments += lines.comments
    assembled = assemble(uri, text, tuple(segments), tuple(comments))
    part = FileCache({uri: text}, {uri: assembled}, options.dialect)
    part.parses.update((u, p) for u, p in cache.parses.items() if u != uri)
    found: list[Diagnostic] = []
    programs: dict[str, Program] = {}
    verified: dict[str, VerifyResult] = {}
    source = SourceInput(uri, text)
    done = _check_one(source, part, modules, plugins, options, found, programs, verified, numbers)
    parsed = part.parses.get(uri)
    if not _stands(uri, found, done, parsed, programs.get(uri), numbers):
        return None
    cache.parses.update((u, p) for u, p in part.parses.items() if u != uri)
    return _outcome(uri, found, done, verified, parsed)


def _runs(chunks: list[groups.Chunk]) -> list[tuple[int, int, int]]:
    """The chunks as runs of adjacent ones: start, end, first line."""
    runs: list[tuple[int, int, int]] = []
    for c in chunks:
        end = c.start + len(c.text)
        if runs and runs[-1][1] == c.start:
            runs[-1] = (runs[-1][0], end, runs[-1][2])
        else:
            runs.append((c.start, end, c.line))
    return runs


def _stands(
    uri: str,
    found: list[Diagnostic],
    done: tuple[bool, int] | None,
    parsed: ParseResult | None,
    program: Program | None,
    numbers: dict[int, int],
) -> bool:
    """Whether a check's outcome can stand for its groups': it has no syntax error, no
    finding that may suggest a name (from any group: ``codes.SUGGESTING``), its
    scenarios are those numbered, in order, and no constraint it left out is written in
    another file (C411 reports those once per file, at the first scenario that uses one)."""
    if done is None or parsed is None or program is None:
        return False
    if any(d.code in codes.SUGGESTING for d in found):
        return False
    if any(d.severity is Severity.ERROR for d in parsed.diagnostics):
        return False
    places = [s.name_span.start if s.name_span is not None else -1 for s in scenarios_of(program)]
    if places != sorted(numbers):
        return False
    return not any(
        d.code.code == "C411" and any(r.span.uri != uri for r in d.related) for d in found
    )


def _outcome(
    uri: str,
    found: list[Diagnostic],
    done: tuple[bool, int] | None,
    verified: dict[str, VerifyResult],
    parsed: ParseResult | None,
) -> groups.Outcome:
    """A check's findings as an outcome: those before the behaviour flow, those after."""
    clean, before = done if done is not None else (False, len(found))
    checked = verified.get(uri)
    return groups.Outcome(
        found[:before],
        found[before:],
        clean,
        checked.unverified() if checked is not None else set(),
        parsed.comment_spans() if parsed is not None else [],
    )


def _load_once(options: AnalysisOptions) -> None:
    """Build what the process builds once (the parser) before any file's budget: the
    first file checked must not pay for it, nor fail to. z3 (about 40 MiB mapped) and
    numpy (the road geometry of a map built when its cache entry is missing, about
    120 MiB) are loaded first under a tight budget only (``memory.PRELOAD_BELOW_MIB``):
    most checks need neither (propagation decides most scenarios without the solver),
    importing z3 is a sixth of a small file's check, and a larger budget has room for
    them when a file does."""
    dialect_reading(parse("import osc.standard\n", ""), options.dialect)
    if options.verify and (options.memory_limit_mib or 0) <= memory.PRELOAD_BELOW_MIB:
        from osc2check.verify.z3_backend import load_z3
        from osc2check.world import geometry  # noqa: F401  (numpy and its libraries)

        load_z3()


def _check_one(
    source: SourceInput,
    cache: FileCache,
    modules: dict[str, str],
    plugins: PluginRegistry | None,
    options: AnalysisOptions,
    found: list[Diagnostic],
    programs: dict[str, Program],
    verified: dict[str, VerifyResult],
    numbers: dict[int, int] | None = None,
) -> tuple[bool, int] | None:
    """Parse, resolve and verify one root file, adding to ``found``, ``programs`` and
    ``verified``; whether it had no error before the behaviour flow, and how many
    findings ``found`` had then (None: a nesting too deep). ``numbers``: the scenarios'
    places among the whole file's (``verify_program``)."""
    start = point_span(source.uri, source.text, 0)
    with memory.analysing(start, "parsing the file"):
        result = cache.read(source.uri)
    if result is None:  # pragma: no cover - sources are always in memory
        return None
    try:
        with memory.analysing(start, "reading its imports and declarations"):
            program = build_program(
                source.uri,
                cache.read,
                options.implicit_imports,
                modules,
                options.search_paths,
                options.library,
            )
    except RecursionError:  # pathological nesting: say so instead of crashing
        found.extend(result.diagnostics)
        found.append(messages.nesting_too_deep(start))
        return None
    programs[source.uri] = program
    found.extend(result.diagnostics)
    own = _relevant(program, result, source.uri)
    found.extend(own)
    if source.problem:
        found.append(_encoding_problem(source))
    clean = not any(d.severity is Severity.ERROR for d in [*result.diagnostics, *own])
    before = len(found)
    if clean:  # the behaviour flow (B codes): no solver, so in every analysis
        found.extend(_flow(program, options.scenario, start))
    if options.verify and clean:
        # the solver's phase (lowering, z3) is imported by the analyses that run it
        from osc2check.verify.check import verify_program

        try:
            checked = verify_program(
                program,
                seed=options.seed,
                scenario=options.scenario,
                rlimit=options.solver_rlimit,
                timeout_ms=options.solver_timeout_ms,
                default_map=options.default_map,
                maps=options.maps,
                plugins=plugins,
                numbers=numbers,
            )
        except RecursionError:
            found.append(messages.nesting_too_deep(start))
            return None
        verified[source.uri] = checked
        found.extend(d for d in checked.diagnostics if d.span.uri == source.uri)
    return clean, before


def _flow(program: Program, scenario: str | None, start: Span) -> list[Diagnostic]:
    """The flow findings, in the root file, of the scenarios declared there (or of the one
    named); ``start`` is the file's start."""
    found: list[Diagnostic] = []
    for sym in scenarios_of(program):
        if scenario is not None and sym.name != scenario:
            continue
        where = sym.name_span or start
        with memory.analysing(where, f"checking the flow of scenario `{sym.name}`"):
            found.extend(d for d in check_flow(program.model, sym) if d.span.uri == start.uri)
    return found


def _clean(source: SourceInput) -> SourceInput:
    """The source with its NUL characters replaced (``source.without_nul``)."""
    text, problem = without_nul(source.text, source.problem)
    if text is source.text:
        return source
    return replace(source, text=text, problem=problem, parse=None)


def _encoding_problem(source: SourceInput) -> Diagnostic:
    """P004 at the first replaced character (or the start of the file)."""
    offset = max(source.text.find("\ufffd"), 0)
    span = point_span(source.uri, source.text, offset)
    if offset < len(source.text):
        span = replace(span, end_column=span.column + 1, end=span.start + 1)
    return messages.invalid_encoding(span, source.problem or "")


# Findings that a missing import or a broken statement explains: reporting them
# too would bury the real problem.
_NAME_CODES = frozenset({"N101", "N103", "N104", "N106", "N108", "N113", "A301", "A302"})


def _relevant(program: Program, result: ParseResult, uri: str) -> list[Diagnostic]:
    own = [d for d in program.diagnostics if d.span.uri == uri]
    missing_import = any(d.code.code == "N105" for d in own)
    return [
        d
        for d in own
        if d.span.line not in result.error_lines
        and not (missing_import and d.code.code in _NAME_CODES)
    ]


def _finish(
    found: list[Diagnostic],
    cache: FileCache,
    comments: dict[str, list[tuple[Span, str]]],
    texts: dict[str, str],
    options: AnalysisOptions,
) -> list[Diagnostic]:
    unique: dict[tuple[str, int, int, str, str], Diagnostic] = {}
    for d in found:
        unique.setdefault((d.span.uri, d.span.start, d.span.end, d.code.code, d.message), d)
    diagnostics = list(unique.values())
    suppressions: list[Suppression] = []
    for uri, text in texts.items():
        result = cache.parses.get(uri)
        found_comments = comments.get(uri)
        if found_comments is None and result is not None:
            found_comments = result.comment_spans()
        if found_comments is not None:
            suppressions.extend(find_suppressions(uri, found_comments, text))
    diagnostics = apply_suppressions(diagnostics, suppressions)
    if options.policy is not None:
        by_uri: dict[str, list[Diagnostic]] = {}
        for d in diagnostics:
            by_uri.setdefault(d.span.uri, []).append(d)
        diagnostics = [d for uri, ds in by_uri.items() for d in options.policy(ds, uri)]
    diagnostics.sort(key=lambda d: d.sort_key)
    return diagnostics
