"""The bundled standard library, parsed and resolved once per process.

``types.osc`` (namespace ``stdtypes``), ``domain.osc`` (``std``) and the
toolkit's own ``osc2toolkit.osc`` form the base model under every program.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

from osc2check import cache
from osc2check.diagnostics import Diagnostic
from osc2check.resources import stdlib_dir
from osc2check.semantics.builtins import STANDARD_MODULE_NAMES
from osc2check.semantics.declare import TOOLKIT_NAMESPACE, Unit
from osc2check.semantics.model import Context, Model
from osc2check.semantics.resolve import resolve
from osc2check.syntax import ParseResult, parse
from osc2check.syntax.grammar import grammar_key

LIBRARY_FILES = ("types.osc", "domain.osc", "osc2toolkit.osc")
STD, STDTYPES = "std", "stdtypes"

# Structured imports of the standard: module -> (namespaces made available, auto-use).
STANDARD_MODULES: dict[str, tuple[tuple[str, ...], bool]] = dict(
    zip(
        STANDARD_MODULE_NAMES,
        (
            ((STD, STDTYPES, TOOLKIT_NAMESPACE), True),
            ((STD, STDTYPES, TOOLKIT_NAMESPACE), False),
            ((STDTYPES,), False),
            ((STD, STDTYPES, TOOLKIT_NAMESPACE), False),
        ),
        strict=True,
    )
)
# The design paper imports the library by file name.
STANDARD_FILE_NAMES = ("domain.osc", "types.osc", "standard.osc")
AUTO_USE = (STD, STDTYPES, TOOLKIT_NAMESPACE)


@dataclass(frozen=True)
class StandardLibrary:
    model: Model
    parses: dict[str, ParseResult]
    diagnostics: tuple[Diagnostic, ...]


_lock = threading.Lock()
_cached: StandardLibrary | None = None


def comment_lines(result: ParseResult) -> dict[int, str]:
    """Comments that stand alone on their line, by line number (doc comments)."""
    lines: dict[int, str] = {}
    text = result.text
    for c in result.comments:
        line_start = max(text.rfind("\n", 0, c.offset), text.rfind("\r", 0, c.offset)) + 1
        if not text[line_start : c.offset].strip():
            lines[c.line] = c.text
    return lines


def standard_library() -> StandardLibrary:
    """The library's model; built on first use, then shared (it is never modified).

    It comes from the start-up cache (``osc2check.cache``) when an entry for this
    toolkit, grammar, library text and Python is there; otherwise it is built and
    stored for the next process.
    """
    global _cached
    with _lock:
        if _cached is None:
            folder = stdlib_dir()
            texts = {str(folder / n): (folder / n).read_text("utf-8") for n in LIBRARY_FILES}
            key = {
                **grammar_key(),
                "library": cache.digest(*texts, *texts.values()),  # its file names are in spans
            }
            _cached = cache.cached("stdlib", key, lambda: _build(texts))
        return _cached


def _build(texts: dict[str, str]) -> StandardLibrary:
    model = Model()
    parses: dict[str, ParseResult] = {}
    units = []
    for uri, text in texts.items():
        result = parse(text, uri)
        parses[uri] = result
        units.append(Unit(uri, result.ast, Context(), library=True, comments=comment_lines(result)))
    diagnostics = [d for r in parses.values() for d in r.diagnostics]
    diagnostics += resolve(model, units)
    return StandardLibrary(model, parses, tuple(diagnostics))
