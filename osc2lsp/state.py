"""Open documents, their snapshots, and when they are analysed.

Each edit (re)starts a short debounce timer for its document; when it runs
out, the document is analysed together with the open documents that import
it (their findings may change) and the open documents it imports (so their
unsaved text is used). A newer edit cancels a timer that has not run out and
makes any analysis still running stale: its snapshots are kept (they are the
best ones available while typing) but only the current version's findings
are published. Analyses run one at a time on a worker thread, so the event
loop keeps answering requests meanwhile.

Findings come in up to three steps:

* **Preview** (documents whose last analysis was slow, ``preview_after``): the
  declarations the edit touched are parsed again and their syntax findings
  published at once with the other findings of the last analysis, moved to
  their new place (``preview.py``). On a 10,000-line document this takes
  milliseconds where the analysis takes most of a second.
* **Analysis** without the solver: syntax, names, types, units, arguments.
* **Solver** (constraints, placement, behaviour flow: z3 for every scenario),
  once the document has been quiet for ``verify_delay`` milliseconds, in a
  worker process (``solver.py``); its findings replace the others when no
  newer edit came meanwhile.

A push that would repeat what the client already has (same version, same
findings) is not sent. Files of the bundled library (opened from a
definition) are analysed as the library and never get findings.

Requests that must see the current text (references, rename, pulled
diagnostics...) await ``fresh(uri)``, which skips the rest of the debounce;
hover and definition use ``latest(uri)`` when the position lies outside what
changed since (``view``); completion and signature help use ``latest(uri)``
and the current text.

An analysis starts from the latest snapshot's parse: the segments the edits
touched are parsed again and spliced into it (``Revision.parse``,
``osc2check.syntax.incremental``), the rest is reused or moved.

A new snapshot's findings are published as soon as the analysis ends; requests see
the snapshot once the indexes they use are built, on the analysis thread
(``_settle``), and the previous snapshot answers meanwhile.

A replaced snapshot is freed by reference counting (the checker's analyses hold
no reference cycles), on the analysis thread: freeing a 10,000-line document's
analysis holds the interpreter lock for a few tens of milliseconds, which a
request would wait for. So replaced snapshots are kept until the documents have
been quiet (no edit, no analysis) for ``QUIET_FREE`` seconds, a pause in
typing, and at most ``MAX_REPLACED`` of them: beyond that the oldest are freed
after the next analysis (``_settle``). The collector is paused while an
analysis runs and what it made is frozen without a scan (``_freeze``); every
generation is collected once the documents have been quiet for
``QUIET_COLLECTION`` seconds.
"""

from __future__ import annotations

import asyncio
import gc
import logging
import re
import time
from collections.abc import Callable, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from osc2check.gc_pause import gc_paused
from osc2lsp.options import CheckerConfigs, Options
from osc2lsp.solver import SolverWorker
from osc2lsp.text import LineIndex, TextMap, uri_to_key
from osc2lsp.view import View

if TYPE_CHECKING:
    from osc2check.diagnostics import Diagnostic
    from osc2check.syntax import ParseResult
    from osc2lsp.snapshot import Snapshot

log = logging.getLogger(__name__)

# The interpreter lock passes between threads every SWITCH seconds (Python's default is
# 5 ms): a request waiting for the analysis thread to give it up waits that long, and
# it waits several times per request (reading, answering).
SWITCH = 0.001
QUIET_FREE = 0.5  # seconds without edits or analyses before replaced snapshots are freed
MAX_REPLACED = 3  # replaced snapshots kept until then, at most (about 13 MB each at 10,000 lines)
QUIET_COLLECTION = 30.0  # seconds without edits or analyses before a full collection

LinesOf = Callable[[str], "LineIndex | None"]


def analyse(
    documents: list[tuple[str, str, int | None]],
    config=None,
    verify: bool = True,
    parses: Mapping[str, ParseResult] | None = None,
) -> dict[str, Snapshot]:
    """Analyse documents given as ``(uri, text, version)``; a snapshot for each.

    Without ``verify`` the solver's checks (C, L and B codes) are left out.
    ``parses`` has parses of documents' texts by uri, to use instead of parsing.
    """
    from osc2check.analysis import SourceInput, analyze  # heavy: imported on first use
    from osc2check.config import Config
    from osc2lsp.snapshot import Snapshot

    keys = {uri: uri_to_key(uri) for uri, _, _ in documents}
    given = parses or {}
    inputs = [SourceInput(keys[uri], text, parse=given.get(uri)) for uri, text, _ in documents]
    config = config if config is not None else Config()
    # the budget is an address-space limit of the whole process: the server's own would
    # bound its transport too, so only the solver worker, a process of its own, has it
    analysis = analyze(inputs, config.analysis_options(verify=verify, memory_limit_mib=None))
    return {
        uri: Snapshot(uri, keys[uri], version, text, analysis, config, verify)
        for uri, text, version in documents
    }


def snapshot_of(
    text: str, uri: str = "file:///tmp/osc2lsp/document.osc", version: int | None = 1, config=None
) -> Snapshot:
    """A snapshot of one text (for tests and scripts)."""
    return analyse([(uri, text, version)], config)[uri]


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
    timer: asyncio.Task | None = None  # the debounce, until the analysis starts
    waiting: bool = False  # the timer has not started its analysis yet (may be cancelled)
    verify_timer: asyncio.Task | None = None  # the quiet period before the solver runs
    waiters: list[tuple[int | None, asyncio.Future]] = field(default_factory=list)
    stale: bool = False  # a file it imports changed since its snapshot was made
    preview: Findings | None = None  # the preview of the current version, if one was made
    delivered: tuple[int | None, str] | None = None  # (version, result id) the client has
    analysis_seconds: float = 0.0  # how long its last analysis took
    _lines: LineIndex | None = field(default=None, repr=False)
    _map: tuple[Snapshot, str, TextMap] | None = field(default=None, repr=False)

    def __post_init__(self):
        if not self.key:
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
        from osc2check.syntax.incremental import Edit, splice

        previous = self.previous
        if previous is None or previous.key != self.key:
            return None
        parsed = previous.parse
        if previous.text == self.text:
            return parsed
        change = TextMap(previous.text, self.text)
        return splice(parsed, self.text, Edit(change.prefix, change.old_end, change.new_end))


Publisher = Callable[[str, list[Findings]], None]


class State:
    """The open documents and their analysis schedule."""

    def __init__(
        self,
        options: Options | None = None,
        publish: Publisher | None = None,
        root: str | None = None,
    ):
        self.options = options or Options()
        self.publish = publish or (lambda trigger, findings: None)
        self.root = root
        self.documents: dict[str, Document] = {}
        self.configs = CheckerConfigs()
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="osc2-analysis")
        self._previews = ThreadPoolExecutor(max_workers=1, thread_name_prefix="osc2-preview")
        self._solver = SolverWorker()
        self._closed: dict[str, tuple[float, str, Snapshot | None]] = {}  # workspace files
        self._lock: asyncio.Lock | None = None
        self._tasks: set[asyncio.Task] = set()
        self._replaced: list[Snapshot] = []  # replaced snapshots, freed once all is quiet
        self._quiet: asyncio.Task | None = None  # what is done once all is quiet

    # ---- documents -------------------------------------------------------------

    def open(self, uri: str, text: str, version: int | None) -> Document:
        doc = self.documents[uri] = Document(uri, text, version)
        self.schedule(uri, 0)
        return doc

    def change(
        self, uri: str, text: str, version: int | None, lines: LineIndex | None = None
    ) -> None:
        doc = self.documents.get(uri)
        if doc is None:
            self.open(uri, text, version)
            return
        doc.set_text(text, version, lines)
        self._when_quiet()
        if doc.verify_timer is not None:
            doc.verify_timer.cancel()
        for other in self.documents.values():
            snap = other.snapshot
            if (
                other is not doc
                and snap is not None
                and snap.program is not None
                and doc.key in snap.program.files
            ):
                other.stale = True
        self.schedule(uri)

    def close(self, uri: str) -> None:
        doc = self.documents.pop(uri, None)
        if doc is None:
            return
        for timer in (doc.timer, doc.verify_timer):
            if timer is not None:
                timer.cancel()
        for _, future in doc.waiters:
            if not future.done():
                future.set_result(None)

    def latest(self, uri: str) -> Snapshot | None:
        """The newest snapshot of ``uri``, which may lag behind the text."""
        doc = self.documents.get(uri)
        return doc.snapshot if doc is not None else None

    async def fresh(self, uri: str) -> Snapshot | None:
        """The snapshot of the current version of ``uri`` (analysing it now if needed)."""
        doc = self.documents.get(uri)
        if doc is None:
            return None
        if doc.current:
            return doc.snapshot
        future = asyncio.get_running_loop().create_future()
        doc.waiters.append((doc.version, future))
        timer = doc.timer
        if timer is None or timer.done() or doc.waiting:
            self.schedule(uri, 0)  # skip the rest of the debounce (a running one will do)
        return await future

    async def view(self, uri: str, offset: int) -> tuple[Snapshot, TextMap | None] | None:
        """A snapshot to answer about ``offset`` of the current text, and how its text
        differs from the current one (None: it is the current text).

        While an analysis runs, the latest snapshot answers for every offset outside
        the text changed since it was made; otherwise the current version's does.
        """
        found = self.view_now(uri, offset)
        if found is not None:
            return found
        snap = await self.fresh(uri)
        return (snap, None) if snap is not None else None

    def view_now(self, uri: str, offset: int) -> tuple[Snapshot, TextMap | None] | None:
        """``view`` if the latest snapshot can answer, else None (without waiting)."""
        doc = self.documents.get(uri)
        if doc is None or doc.snapshot is None:
            return None
        changes = doc.changes()
        if changes is not None and (changes.unchanged or changes.clear_of(offset)):
            return doc.snapshot, None if changes.unchanged else changes
        return None

    async def fresh_all(self) -> list[Snapshot]:
        """The snapshots of the current versions of every open document."""
        snapshots = [await self.fresh(uri) for uri in list(self.documents)]
        return [s for s in snapshots if s is not None]

    async def findings_now(self, uri: str, preview: bool) -> Findings | None:
        """The findings of the current version for a client that asks for them: the
        preview when ``preview`` and the analysis is slow, else the analysis'."""
        doc = self.documents.get(uri)
        if doc is None:
            return None
        if preview and not doc.current and self._preview_due(doc):
            if doc.preview is None or doc.preview.version != doc.version:
                await self._preview(doc)
            if doc.preview is not None and doc.preview.version == doc.version:
                return doc.preview
        snap = await self.fresh(uri)
        return findings_of(snap) if snap is not None else None

    async def analysed(self) -> None:
        """Wait until the scheduled analyses are done (for tests and benchmarks)."""
        while True:
            pending = [d.timer for d in self.documents.values() if d.timer and not d.timer.done()]
            if not pending:
                return
            await asyncio.wait(pending)

    async def quiet(self) -> None:
        """``analysed``, then free the replaced snapshots at once, as a quiet spell
        does (for tests and benchmarks)."""
        await self.analysed()
        if self._replaced:
            freed, self._replaced = self._replaced, []
            await asyncio.get_running_loop().run_in_executor(self._executor, freed.clear)

    def delivered(self, uri: str, findings: Findings) -> None:
        """Note that the client has received ``findings`` (pulled them)."""
        from osc2lsp.features.diagnostics import result_id

        doc = self.documents.get(uri)
        if doc is not None:
            doc.delivered = (findings.version, result_id(findings.diagnostics))

    def reconfigure(self, options: Options) -> None:
        self.options = options
        for uri, doc in list(self.documents.items()):
            doc.stale = True
            self.schedule(uri, 0)

    # ---- scheduling --------------------------------------------------------------

    def schedule(self, uri: str, delay_ms: int | None = None) -> None:
        """(Re)start the debounce timer of ``uri``."""
        doc = self.documents.get(uri)
        if doc is None:
            return
        if doc.timer is not None and not doc.timer.done() and doc.waiting:
            doc.timer.cancel()
        delay = self.options.debounce if delay_ms is None else delay_ms
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return
        task = loop.create_task(self._run(uri, delay / 1000))
        doc.timer, doc.waiting = task, True
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _run(self, uri: str, delay: float) -> None:
        task = asyncio.current_task()
        if delay > 0:
            await asyncio.sleep(delay)
            doc = self.documents.get(uri)
            if doc is not None and self._preview_due(doc):
                await self._preview(doc)
        if self._lock is None:
            self._lock = asyncio.Lock()
        async with self._lock:
            doc = self.documents.get(uri)
            if doc is not None and doc.timer is task:
                doc.waiting = False
            if doc is None or doc.current:
                self._wake(doc)
                return
            batch = [doc] if doc.library else self._batch(doc)
            for member in batch:
                member.stale = False
            if self._quiet is not None:
                self._quiet.cancel()  # not quiet
            loop = asyncio.get_running_loop()
            began = time.perf_counter()
            revisions = [Revision.of(d) for d in batch]
            try:
                snapshots = await loop.run_in_executor(self._executor, self._analyse, revisions)
            except Exception:  # an internal error of the checker: keep serving
                log.exception("analysis of %s failed", uri)
                snapshots = {}
            doc.analysis_seconds = time.perf_counter() - began
            del revisions  # they hold the replaced snapshots
            published: list[Findings] = []
            taken: list[tuple[Document, Snapshot]] = []
            for d in batch:
                snap = snapshots.get(d.uri)
                if snap is None or self.documents.get(d.uri) is not d:
                    continue
                if d.snapshot is None:
                    d.replace_snapshot(snap)  # nothing older to answer from meanwhile
                elif not _newer(d.snapshot.version, snap.version):
                    taken.append((d, snap))
                if snap.version == d.version:
                    published.append(findings_of(snap))
            self._publish(uri, published)
            # Requests see the new snapshots once their indexes are built (on the
            # analysis thread); until then the previous ones answer.
            replaced = self._replaced
            oldest = replaced[: max(len(replaced) + len(taken) - MAX_REPLACED, 0)]
            del replaced[: len(oldest)]
            if snapshots or oldest:
                built = list(snapshots.values())
                try:
                    await loop.run_in_executor(self._executor, _settle, built, oldest)
                except Exception:  # requests build what is missing
                    log.exception("preparing the snapshots of %s failed", uri)
            for d, snap in taken:
                if self.documents.get(d.uri) is d and d.snapshot is not None:
                    self._replaced.append(d.snapshot)  # (a quiet spell may have renewed it)
                    d.replace_snapshot(snap)
            for d in batch:
                if d.uri in snapshots and self.documents.get(d.uri) is d:
                    self._wake(d)
            if self.options.verify and published and not doc.library:
                self._schedule_solver(uri)
            self._when_quiet()

    def _when_quiet(self) -> None:
        """(Re)start the wait for a quiet spell: after ``QUIET_FREE`` seconds without
        edits or analyses the replaced snapshots are freed, after ``QUIET_COLLECTION``
        every generation is collected once."""
        if self._quiet is not None:
            self._quiet.cancel()
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return

        async def after_quiet() -> None:
            await asyncio.sleep(QUIET_FREE)
            if self._replaced:
                freed, self._replaced = self._replaced, []
                await loop.run_in_executor(self._executor, freed.clear)
            await asyncio.sleep(QUIET_COLLECTION - QUIET_FREE)
            await loop.run_in_executor(self._executor, _collect_all)

        self._quiet = task = loop.create_task(after_quiet())
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    def _analyse(self, batch: list[Revision]) -> dict[str, Snapshot]:
        """Snapshots of the batch's texts (on the analysis thread)."""
        from osc2lsp.snapshot import library_snapshot

        doc = batch[0]
        if doc.library:
            return {doc.uri: library_snapshot(doc.uri, doc.key, doc.text, doc.version)}
        config = self.configs.for_file(doc.key, self.options, self.root)
        with gc_paused():
            parses = {r.uri: p for r in batch if (p := r.parse()) is not None}
            found = analyse([(r.uri, r.text, r.version) for r in batch], config, False, parses)
            _freeze()
        return found

    def _publish(self, trigger: str, findings: list[Findings]) -> None:
        """Hand findings the client does not have yet to the publisher."""
        from osc2lsp.features.diagnostics import result_id

        news = []
        for f in findings:
            doc = self.documents.get(f.uri)
            if doc is None or doc.library:
                continue
            seen = (f.version, result_id(f.diagnostics))
            if doc.delivered == seen:
                continue
            news.append(f)
        if not news:
            return
        try:
            self.publish(trigger, news)
        except Exception:
            log.exception("publishing diagnostics failed")

    def pushed(self, findings: Findings) -> None:
        """Note that ``findings`` were pushed to the client."""
        self.delivered(findings.uri, findings)

    # ---- the preview -------------------------------------------------------------------

    def _preview_due(self, doc: Document) -> bool:
        snap = doc.snapshot
        return (
            not doc.library
            and snap is not None
            and snap.version != doc.version
            and doc.analysis_seconds * 1000 >= self.options.preview_after
        )

    async def _preview(self, doc: Document) -> None:
        from osc2lsp.preview import preview

        snap, lines, version = doc.snapshot, doc.lines, doc.version
        assert snap is not None
        loop = asyncio.get_running_loop()
        try:
            found = await loop.run_in_executor(self._previews, preview, snap, lines)
        except Exception:
            log.exception("preview of %s failed", doc.uri)
            return
        if found is None or self.documents.get(doc.uri) is not doc or doc.version != version:
            return
        if doc.snapshot is not None and doc.snapshot.version == version:
            return  # the analysis was quicker
        lines_of = View(snap, None, lines).lines_of  # the current text for the document
        doc.preview = Findings(doc.uri, doc.key, version, tuple(found), lines_of, final=False)
        self._publish(doc.uri, [doc.preview])

    # ---- the solver's phase ------------------------------------------------------------

    def _schedule_solver(self, uri: str) -> None:
        doc = self.documents.get(uri)
        if doc is None:
            return
        if doc.verify_timer is not None:
            doc.verify_timer.cancel()
        task = asyncio.get_running_loop().create_task(
            self._solve(uri, self.options.verify_delay / 1000)
        )
        doc.verify_timer = task
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    @property
    def solver(self) -> SolverWorker:
        return self._solver

    @property
    def executor(self) -> ThreadPoolExecutor:
        """The analysis thread (one job at a time)."""
        return self._executor

    async def _solve(self, uri: str, delay: float) -> None:
        """The findings of the solver's checks for a document that has been quiet."""
        if delay > 0:
            await asyncio.sleep(delay)
        doc = self.documents.get(uri)
        if doc is None or not doc.current:
            return  # a newer edit is on its way; its analysis schedules this again
        batch = self._batch(doc)
        texts = {d.uri: (d.version, d.text) for d in batch}
        config = self.configs.for_file(doc.key, self.options, self.root)
        jobs = [(d.key, d.version, d.text) for d in batch]
        try:
            answer = await self._solver.findings(jobs, config)
        except Exception:
            log.exception("solver checks of %s failed", uri)
            return
        published = []
        for d in batch:
            if self.documents.get(d.uri) is not d or d.stale or not d.current:
                continue
            # The answer is for the versions asked about, and the document is still at
            # that version with that text: else a newer analysis is on its way.
            if (
                (d.version, d.text) == texts[d.uri]
                and answer.versions.get(d.key, -1) == d.version
                and d.key in answer.findings
                and d.snapshot
            ):
                d.snapshot = d.snapshot.with_findings(answer.findings[d.key])
                published.append(findings_of(d.snapshot))
        self._publish(uri, published)

    def _wake(self, doc: Document | None) -> None:
        if doc is None or doc.snapshot is None:
            return
        remaining = []
        for version, future in doc.waiters:
            if future.done():
                continue
            if doc.snapshot.version == doc.version or not _newer(version, doc.snapshot.version):
                future.set_result(doc.snapshot)
            else:
                remaining.append((version, future))
        doc.waiters = remaining
        if remaining and (doc.timer is None or doc.timer.done()):
            self.schedule(doc.uri, 0)

    def _batch(self, doc: Document) -> list[Document]:
        """The document, the open documents that import it, and those it imports."""
        batch = {doc.uri: doc}
        by_key = {d.key: d for d in self.documents.values() if not d.library}
        for other in self.documents.values():
            snap = other.snapshot
            if (
                other is not doc
                and not other.library
                and snap is not None
                and snap.program is not None
                and doc.key in snap.program.files
            ):
                batch[other.uri] = other
        for member in list(batch.values()):
            snap = member.snapshot
            if snap is not None and snap.program is not None:
                for key in snap.program.files:
                    if key in by_key:
                        batch.setdefault(by_key[key].uri, by_key[key])
        return list(batch.values())

    async def closed_files(self, mentioning: str, limit: int = 200) -> list[Snapshot]:
        """Snapshots of the workspace's `.osc` files that are not open and whose text
        contains ``mentioning`` (references and rename reach into them).

        The files are found and read as ``osc2check`` finds and reads them (regular
        files only, at most its size cap, never blocking) on a thread of their own:
        a slow or strange file system never holds up the event loop.
        """
        if not self.root:
            return []
        open_keys = {d.key for d in self.documents.values()}
        known = {key: (mtime, text) for key, (mtime, text, _) in self._closed.items()}
        loop = asyncio.get_running_loop()
        read = await loop.run_in_executor(
            None, _workspace_sources, Path(self.root), limit, open_keys, known, mentioning
        )
        found: list[Snapshot] = []
        for key, mtime, text, mentions in read:
            cached = self._closed.get(key)
            if cached is None or cached[0] != mtime or cached[1] is not text:
                cached = self._closed[key] = (mtime, text, None)
            if not mentions:
                continue
            snap = cached[2]
            if snap is None:
                config = self.configs.for_file(key, self.options, self.root)
                uri = Path(key).as_uri()
                inputs: list[tuple[str, str, int | None]] = [(uri, text, None)]
                analysed = await loop.run_in_executor(
                    self._executor, analyse, inputs, config, False
                )
                snap = analysed[uri]
                self._closed[key] = (mtime, text, snap)
            found.append(snap)
        return found

    async def shutdown(self) -> None:
        """Cancel the timers and stop the workers (a running solver job is killed)."""
        for task in list(self._tasks):
            task.cancel()
        self._executor.shutdown(wait=False, cancel_futures=True)
        self._previews.shutdown(wait=False, cancel_futures=True)
        await self._solver.stop()

    def kill(self) -> None:
        """Stop the solver worker now (the server is leaving without a shutdown)."""
        self._solver.kill()


def _settle(snapshots: list[Snapshot], replaced: list[Snapshot]) -> None:
    """After an analysis, on its thread: ``replaced`` freed (it holds their last
    references) and what requests will need of ``snapshots`` built now."""
    replaced.clear()
    with gc_paused():
        for snap in snapshots:
            snap.prepare()
            _warm_features(snap)
        _freeze()


def _freeze() -> None:
    """Exempt every object made so far from the collector's scans, without a scan.

    An analysis makes its objects with the collector paused; when the pause ended,
    the first allocation would start a collection that scans them all at once (tenths
    of a second on a 10,000-line document, holding the interpreter lock while a
    request waits). Analyses hold no reference cycles, so nothing is lost by not
    scanning them: a frozen object is still freed when its last reference goes.
    What cycles other code left meanwhile are collected when the documents are
    quiet (``_collect_all``).
    """
    gc.freeze()


def _collect_all() -> None:
    """Collect every generation, the frozen objects included, then freeze the survivors
    (after a quiet period: it holds the interpreter lock for tenths of a second)."""
    gc.unfreeze()
    gc.collect()
    gc.freeze()


def _warm_features(snap: Snapshot) -> None:
    """Ask for a completion and a hover once, on the analysis thread: what they keep
    per snapshot (or load on first use) is then ready for the requests that follow."""
    from osc2lsp.features.completion import complete
    from osc2lsp.features.hover import hover

    try:
        complete(snap, snap.text, 0)
        names = snap.names
        if names:
            hover(snap, names[len(names) // 2].start)
    except Exception:  # the request itself will report it
        log.debug("warming the features failed", exc_info=True)


def _workspace_sources(
    root: Path,
    limit: int,
    open_keys: set[str],
    known: dict[str, tuple[float, str]],
    mentioning: str,
) -> list[tuple[str, float, str, bool]]:
    """``(key, mtime, text, mentions)`` of the first ``limit`` sources below ``root``
    that are not open (the text of ``known`` when the file has not changed since), as
    ``osc2check`` walks and reads them; the folders it skips by default, hidden ones and
    the bundled library are left out. ``mentions``: the text has ``mentioning`` as a
    whole word. On a thread: it reads files."""
    from osc2check.config import DEFAULT_EXCLUDE
    from osc2check.inputs import InputError, read_bytes, walk
    from osc2check.resources import stdlib_dir
    from osc2check.source import decode_source

    library = stdlib_dir().resolve()

    def excluded(path: Path) -> bool:
        name = path.name
        if name.endswith(".osc"):
            return False
        return name in DEFAULT_EXCLUDE or name.startswith(".") or path.resolve() == library

    if not root.is_dir():
        return []
    word = re.compile(rf"(?<!\w){re.escape(mentioning)}(?!\w)")
    found = []
    for met in walk(root, excluded):
        if met.why is not None:
            log.debug("workspace search: %s left out: %s", met.path, met.why)
            continue
        key = str(met.path)
        if key in open_keys:
            continue
        try:
            mtime = met.path.stat().st_mtime
            cached = known.get(key)
            if cached is not None and cached[0] == mtime:
                text = cached[1]
            else:
                text, _ = decode_source(read_bytes(met.path))
        except (OSError, InputError) as exc:
            log.debug("workspace search: %s left out: %s", met.path, exc)
            continue
        found.append((key, mtime, text, bool(word.search(text))))
        if len(found) >= limit:
            break
    return found


def _newer(a: int | None, b: int | None) -> bool:
    if a is None or b is None:
        return True
    return a > b
