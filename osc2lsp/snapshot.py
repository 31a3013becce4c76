"""An analysis snapshot of one document version, and the position helpers on it.

A ``Snapshot`` is immutable: the text of one version of a document, the
``osc2check`` analysis that was made of it, and indexes built lazily on first
use. Features take a snapshot and a code-point offset into its text; they
never see LSP positions (``convert.py`` does that translation).

Two names exist for every file: the *uri* the client uses (``file:///...``,
``untitled:...``) and the *key* the analysis uses (a file-system path for
``file:`` URIs, since imports are resolved relative to it, else the URI).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from osc2check.analysis import Analysis
from osc2check.diagnostics import Diagnostic
from osc2check.resources import stdlib_dir
from osc2check.semantics.model import Model
from osc2check.semantics.profile import DEFAULT_OSC_VERSION, OSC_VERSIONS
from osc2check.semantics.program import Program
from osc2check.semantics.stdlib import StandardLibrary, standard_library
from osc2check.semantics.symbols import Symbol
from osc2check.syntax import ParseResult, ast, parse
from osc2lsp.lazy import cached_property
from osc2lsp.text import LineIndex, key_to_uri, uri_to_key

__all__ = [
    "LineIndex",
    "NameEntry",
    "Snapshot",
    "key_to_uri",
    "library_key",
    "library_snapshot",
    "symbol_key",
    "uri_to_key",
]

# ---- the snapshot -------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class NameEntry:
    """A name in the document and the symbol it refers to (or declares)."""

    start: int
    end: int
    name: ast.Name
    symbol: Symbol


def symbol_key(symbol: Symbol) -> tuple[object, ...]:
    """Identity of a declaration across analyses (each program builds its own symbols)."""
    span = symbol.name_span
    return (
        symbol.uri or (span.uri if span else ""),
        span.start if span else -1,
        symbol.name,
        symbol.kind,
    )


# The cached properties of a snapshot that depend on its text and analysis only (not
# on its findings): a snapshot with the solver's findings keeps them.
_INDEXES = frozenset({"lines", "parse", "program", "model", "_names_by_file", "_name_starts"})


@dataclass(frozen=True, eq=False)
class Snapshot:
    """One version of one document and what the analysis found in it."""

    uri: str
    key: str
    version: int | None
    text: str
    analysis: Analysis
    config: object = None
    verified: bool = True  # the findings include the solver's checks (C, L, B codes)
    findings: tuple[Diagnostic, ...] | None = None  # all findings, from the solver process
    _cache: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    @cached_property
    def lines(self) -> LineIndex:
        return LineIndex(self.text)

    @cached_property
    def parse(self) -> ParseResult:
        found = self.analysis.parses.get(self.key)
        return found if found is not None else parse(self.text, self.key)

    @cached_property
    def program(self) -> Program | None:
        return self.analysis.programs.get(self.key)

    @cached_property
    def model(self) -> Model:
        program = self.program
        if program is not None:
            return program.model
        return Model(base=self.library.model)

    @cached_property
    def library(self) -> StandardLibrary:
        """The standard library of this document's program (its OSC2 version's)."""
        program = self.program
        return standard_library(program.library.version) if program else standard_library()

    @property
    def ast(self) -> ast.File:
        return self.parse.ast

    @cached_property
    def diagnostics(self) -> list[Diagnostic]:
        if self.findings is not None:
            return list(self.findings)
        return [d for d in self.analysis.diagnostics if d.span.uri == self.key]

    def prepare(self) -> Snapshot:
        """Build the indexes requests use (line starts, names by position) now, on the
        analysis thread, rather than in the first request that needs them (on a
        10,000-line document that takes a tenth of a second)."""
        _ = self.lines, self._name_starts
        return self

    def with_findings(self, findings: list[Diagnostic]) -> Snapshot:
        """This snapshot with the complete findings (the solver's checks included), and
        the indexes this one has built (the first request would build them again)."""
        found = replace(self, verified=True, findings=tuple(findings), _cache=self._cache)
        built = {k: v for k, v in vars(self).items() if k in _INDEXES}
        vars(found).update(built)
        return found

    @cached_property
    def _names_by_file(self) -> dict[str, list[NameEntry]]:
        by_file: dict[str, list[NameEntry]] = {}
        for name, sym in self.model.references.items():
            if name.text:
                span = name.span
                by_file.setdefault(span.uri, []).append(NameEntry(span.start, span.end, name, sym))
        for entries in by_file.values():
            entries.sort(key=lambda e: e.start)
        return by_file

    @property
    def names(self) -> list[NameEntry]:
        """Every resolved name of this document, ordered by offset."""
        return self._names_by_file.get(self.key, [])

    def names_in(self, key: str) -> list[NameEntry]:
        """Every resolved name of file ``key`` of this document's program."""
        return self._names_by_file.get(key, [])

    @cached_property
    def _name_starts(self) -> list[int]:
        return [e.start for e in self.names]

    def name_at(self, offset: int) -> NameEntry | None:
        """The resolved name under ``offset`` (a cursor at either end counts)."""
        i = bisect.bisect_right(self._name_starts, offset) - 1
        best = None
        for j in (i, i - 1):
            if 0 <= j < len(self.names):
                entry = self.names[j]
                if entry.start <= offset <= entry.end:
                    if best is None or entry.start <= offset < entry.end:
                        best = entry
        return best

    def text_of(self, key: str) -> str | None:
        """The text of any file the analysis read (the document, imports, the library)."""
        if key == self.key:
            return self.text
        if key in self.analysis.texts:
            return self.analysis.texts[key]
        found = self.analysis.parses.get(key)
        if found is not None:
            return found.text
        library = self.library.parses.get(key)
        if library is not None:
            return library.text
        return None

    def lines_of(self, key: str) -> LineIndex | None:
        if key == self.key:
            return self.lines
        cache = self._cache.setdefault("lines", {})
        if key not in cache:
            text = self.text_of(key)
            cache[key] = LineIndex(text) if text is not None else None
        found: LineIndex | None = cache[key]
        return found

    def parse_of(self, key: str) -> ParseResult | None:
        if key == self.key:
            return self.parse
        found = self.analysis.parses.get(key)
        if found is None:
            found = self.library.parses.get(key)
        return found

    def files(self) -> list[str]:
        """The keys of the files of this document's program (itself first)."""
        keys = [self.key]
        if self.program is not None:
            keys += [k for k in self.program.files if k != self.key]
        return keys

    def offset(self, line: int, column: int) -> int:
        return self.lines.offset(line, column)


# ---- files of the bundled library --------------------------------------------------


def library_key(key: str) -> str | None:
    """The library's own name of ``key`` when it is a file of the bundled library
    (opened from a definition, say), else None."""
    if "://" in key or not key.endswith(".osc"):
        return None
    path = Path(key)
    try:
        folder = path.parent.resolve()
    except OSError:
        return None
    library = stdlib_dir()
    for version_folder in (library, *(library / v for v in OSC_VERSIONS)):
        if folder == version_folder.resolve():
            return str(version_folder / path.name)
    return None


def library_snapshot(uri: str, key: str, text: str, version: int | None) -> Snapshot:
    """A library file as the library was analysed: its names resolve to the library's
    declarations and it has no findings of its own (the library is not user code).

    When the text differs from the shipped file (edited in the editor), it is read
    as text only: outline and folding, no names.
    """
    folder = Path(key).parent.name
    library = standard_library(folder if folder in OSC_VERSIONS else DEFAULT_OSC_VERSION)
    parsed = library.parses.get(key)
    programs: dict[str, Program] = {}
    if parsed is not None and parsed.text == text:
        programs[key] = Program(key, library.model, files={key: parsed})
    else:
        parsed = parse(text, key)
    analysis = Analysis([], {key: text}, programs, {key: parsed})
    return Snapshot(uri, key, version, text, analysis, None, True, ())
