"""The bundled standard library, parsed and resolved once per process and version.

``types.osc`` (namespace ``stdtypes``), ``domain.osc`` (``std``), the
toolkit's own ``osc2toolkit.osc`` and CARLA's world ``carla.osc`` (``carla``,
imported as ``osc2toolkit.carla``) form the base model under every program: the
2.1.0 library. For 2.2 (:data:`~osc2check.semantics.profile.OSC_VERSIONS`),
``2.2/domain.osc`` lists what 2.2.0 adds: its ``extend`` declarations extend,
and a modifier it declares under a name ``domain.osc`` declares already gains
its parameters (:func:`merged_with`), since the language cannot extend a
modifier.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, replace

from osc2check import cache
from osc2check.diagnostics import Diagnostic
from osc2check.resources import stdlib_dir
from osc2check.semantics.builtins import STANDARD_MODULE_NAMES
from osc2check.semantics.declare import TOOLKIT_NAMESPACE, Unit
from osc2check.semantics.model import Context, Model
from osc2check.semantics.profile import DEFAULT_OSC_VERSION, OSC_VERSIONS
from osc2check.semantics.resolve import resolve
from osc2check.syntax import ParseResult, ast, parse
from osc2check.syntax.grammar import grammar_key

LIBRARY_FILES = ("types.osc", "domain.osc", "osc2toolkit.osc", "carla.osc")
# What a version adds to the 2.1 files: the file that it merges into (see the docstring).
VERSION_FILES: dict[str, dict[str, str]] = {"2.2": {"domain.osc": "2.2/domain.osc"}}
STD, STDTYPES, CARLA = "std", "stdtypes", "carla"
AUTO_USE = (STD, STDTYPES, TOOLKIT_NAMESPACE)
_ALL = (STD, STDTYPES, TOOLKIT_NAMESPACE)

# Structured imports of the library: module -> (namespaces made available, put in use).
STANDARD_MODULES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = dict(
    zip(
        STANDARD_MODULE_NAMES,
        (
            (_ALL, AUTO_USE),
            (_ALL, ()),
            ((STDTYPES,), ()),
            (_ALL, ()),
            ((*_ALL, CARLA), (*AUTO_USE, CARLA)),
        ),
        strict=True,
    )
)
# The design paper imports the library by file name.
STANDARD_FILE_NAMES = ("domain.osc", "types.osc", "standard.osc")


@dataclass(frozen=True)
class StandardLibrary:
    model: Model
    parses: dict[str, ParseResult]
    diagnostics: tuple[Diagnostic, ...]


_lock = threading.Lock()
_cached: dict[str, StandardLibrary] = {}


def comment_lines(result: ParseResult) -> dict[int, str]:
    """Comments that stand alone on their line, by line number (doc comments)."""
    lines: dict[int, str] = {}
    text = result.text
    for c in result.comments:
        line_start = max(text.rfind("\n", 0, c.offset), text.rfind("\r", 0, c.offset)) + 1
        if not text[line_start : c.offset].strip():
            lines[c.line] = c.text
    return lines


def merged_with(base: ast.File, additions: ast.File) -> tuple[ast.File, ast.File]:
    """``base`` with each modifier that ``additions`` declares again given the added
    parameters, and ``additions`` without those declarations."""
    added: dict[str, ast.ModifierDecl] = {
        str(d.name): d for d in additions.declarations if isinstance(d, ast.ModifierDecl)
    }
    merged: list[ast.Declaration] = []
    for decl in base.declarations:
        more = added.pop(str(decl.name), None) if isinstance(decl, ast.ModifierDecl) else None
        if isinstance(decl, ast.ModifierDecl) and more is not None:
            decl = replace(decl, members=decl.members + more.members)
        merged.append(decl)
    kept = tuple(
        d
        for d in additions.declarations
        if not isinstance(d, ast.ModifierDecl) or str(d.name) in added
    )
    return replace(base, declarations=tuple(merged)), replace(additions, declarations=kept)


def standard_library(version: str = DEFAULT_OSC_VERSION) -> StandardLibrary:
    """The library's model for OSC2 ``version``; built on first use, then shared (it is
    never modified).

    It comes from the start-up cache (``osc2check.cache``) when an entry for this
    toolkit, grammar, version, library text and Python is there; otherwise it is built
    and stored for the next process. The dialect is not in the key: it changes how a
    file is read, not the library (``semantics.profile.LibraryChoice``).
    """
    if version not in OSC_VERSIONS:
        raise ValueError(f"no standard library for OSC2 version {version!r}")
    with _lock:
        found = _cached.get(version)
        if found is None:
            folder = stdlib_dir()
            names = [*LIBRARY_FILES, *VERSION_FILES.get(version, {}).values()]
            texts = {str(folder / n): (folder / n).read_text("utf-8") for n in names}
            key = {
                **grammar_key(),
                "version": version,
                "library": cache.digest(*texts, *texts.values()),  # its file names are in spans
            }
            found = _cached[version] = cache.cached("stdlib", key, lambda: _build(version, texts))
        return found


def _build(version: str, texts: dict[str, str]) -> StandardLibrary:
    """The library of ``version`` from its files' ``texts`` (by path)."""
    folder = stdlib_dir()
    parses: dict[str, ParseResult] = {}

    def read(name: str) -> ParseResult:
        uri = str(folder / name)
        parses[uri] = result = parse(texts[uri], uri)
        return result

    def unit(result: ParseResult, file: ast.File) -> Unit:
        return Unit(result.uri, file, Context(), library=True, comments=comment_lines(result))

    units: list[Unit] = []
    for name in LIBRARY_FILES:
        result = read(name)
        addition = VERSION_FILES.get(version, {}).get(name)
        if addition is None:
            units.append(unit(result, result.ast))
            continue
        more = read(addition)
        file, rest = merged_with(result.ast, more.ast)
        units += [unit(result, file), unit(more, rest)]
    model = Model()
    diagnostics = [d for r in parses.values() for d in r.diagnostics]
    diagnostics += resolve(model, units)
    return StandardLibrary(model, parses, tuple(diagnostics))
