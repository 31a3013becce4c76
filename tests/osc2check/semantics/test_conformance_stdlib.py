"""The project's own standard library (``stdlib/*.osc``) parses and resolves cleanly."""

from __future__ import annotations

from pathlib import Path

from osc2check.semantics.stdlib import LIBRARY_FILES, standard_library


def test_the_standard_library_reports_nothing():
    library = standard_library()
    assert sorted(Path(p).name for p in library.parses) == sorted(LIBRARY_FILES)
    assert [(d.span.uri, d.span.line, d.code.code, d.message) for d in library.diagnostics] == []
