"""An open document, the findings to show for one of its versions, and what its
analysis reads (``Revision``, taken on the event loop while the document changes on)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from osc2lsp.text import LineIndex, TextMap, uri_to_key

if TYPE_CHECKING:
    from osc2check.diagnostics import Diagnostic
    from osc2check.syntax import ParseResult
    from osc2lsp.snapshot import Snapshot

LinesOf = Callable[[str], "LineIndex | None"]


@dataclass(frozen=True, eq=False)
class Findings:
    """The diagnostics to show for one version of one document."""

    uri: str
    key: str
    version: int | None
    diagnostics: tuple[Diagnostic, ...]
    lines_of: LinesOf  # the text of each file the findings point into
    final: bool = True  # False: a preview; the analysis follows
    verified: bool = False  # the solver's checks are included


def findings_of(snapshot: Snapshot) -> Findings:
    return Findings(
        snapshot.uri,
        snapshot.key,
        snapshot.version,
        tuple(snapshot.diagnostics),
        snapshot.lines_of,
        True,
        snapshot.verified,
    )


@dataclass(eq=False)
class Document:
    uri: str
    text: str
    version: int | None
    key: str = ""
    library: bool = False  # a file of the bundled library: analysed as the library
    snapshot: Snapshot | None = None  # the latest analysis, maybe of an older version
    timer: asyncio.Task[None] | None = None  # the debounce, until the analysis starts
    waiting: bool = False  # the timer has not started its analysis yet (may be cancelled)
    verify_timer: asyncio.Task[None] | None = None  # the quiet period before the solver runs
    waiters: list[tuple[int | None, asyncio.Future[Snapshot | None]]] = field(default_factory=list)
    stale: bool = False  # a file it imports changed since its snapshot was made
    preview: Findings | None = None  # the preview of the current version, if one was made
    delivered: tuple[int | None, str] | None = None  # (version, result id) the client has
    analysis_seconds: float = 0.0  # how long its last analysis took
    _lines: LineIndex | None = field(default=None, repr=False)
    _map: tuple[Snapshot, str, TextMap] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if not self.key:
            # imported on first use: osc2lsp.snapshot brings the analysis (136 ms measured
            # after osc2lsp.server), not needed to answer `initialize`
            from osc2lsp.snapshot import library_key

            key = uri_to_key(self.uri)
            library = library_key(key)
            self.key, self.library = (library, True) if library else (key, False)

    @property
    def lines(self) -> LineIndex:
        """The line index of the current text (computed once per text)."""
        if self._lines is None or self._lines.text is not self.text:
            self._lines = LineIndex(self.text)
        return self._lines

    def replace_snapshot(self, snapshot: Snapshot) -> None:
        """Make ``snapshot`` the latest, and forget what referred to the one before."""
        self.snapshot = snapshot
        self._map = None
        if self.preview is not None and self.preview.version == snapshot.version:
            self.preview = None  # the analysis of its version replaces it

    def set_text(self, text: str, version: int | None, lines: LineIndex | None = None) -> None:
        self.text, self.version = text, version
        self._lines = lines if lines is not None and lines.text is text else None
        if self.preview is not None and self.preview.version != version:
            self.preview = None

    @property
    def current(self) -> bool:
        return (
            self.snapshot is not None and self.snapshot.version == self.version and not self.stale
        )

    def changes(self) -> TextMap | None:
        """How the current text differs from the latest snapshot's (None: no snapshot)."""
        snap = self.snapshot
        if snap is None:
            return None
        if self._map is None or self._map[0] is not snap or self._map[1] is not self.text:
            self._map = (snap, self.text, TextMap(snap.text, self.text))
        return self._map[2]


@dataclass(frozen=True)
class Revision:
    """What the analysis of one document reads, taken on the event loop (the
    document changes there meanwhile)."""

    uri: str
    key: str
    text: str
    version: int | None
    library: bool
    previous: Snapshot | None  # the latest snapshot, maybe of an older text

    @classmethod
    def of(cls, doc: Document) -> Revision:
        return cls(doc.uri, doc.key, doc.text, doc.version, doc.library, doc.snapshot)

    def parse(self) -> ParseResult | None:
        """The parse of ``text`` made from the previous snapshot's: that parse when the
        text is the same, else with the segments the edits touched parsed again (None:
        parse it whole)."""
        # imported on first use: 34 ms measured after osc2lsp.server, on the analysis
        # thread rather than before `initialize` is answered
        from osc2check.syntax.incremental import parse_from

        previous = self.previous
        if previous is None or previous.key != self.key:
            return None
        return parse_from(previous.parse, self.text)


def newer(a: int | None, b: int | None) -> bool:
    """Whether version ``a`` is newer than ``b`` (an unknown version always is)."""
    if a is None or b is None:
        return True
    return a > b
