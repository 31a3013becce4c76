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
(``memory.settle``), and the previous snapshot answers meanwhile.

Replaced snapshots are freed, and the collector runs, when the documents are
quiet (``memory.py``). The documents are ``documents.py``; closed files of the
workspace that references reach into are read by ``workspace.py``.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

from osc2check.gc_pause import gc_paused
from osc2lsp.options import CheckerConfigs, Options
from osc2lsp.session.analysis import analyse
from osc2lsp.session.documents import Document, Findings, Revision, findings_of, newer
from osc2lsp.session.memory import Replaced, freeze, settle
from osc2lsp.session.solver import SolverWorker
from osc2lsp.session.view import View
from osc2lsp.session.workspace import workspace_sources
from osc2lsp.text import LineIndex, TextMap

if TYPE_CHECKING:
    from osc2lsp.snapshot import Snapshot

log = logging.getLogger(__name__)


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
        self._tasks: set[asyncio.Task[Any]] = set()
        self._replaced = Replaced(self._executor, self._tasks)  # freed once all is quiet

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
        self._replaced.when_quiet()
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
        future: asyncio.Future[Snapshot | None] = asyncio.get_running_loop().create_future()
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
        await self._replaced.free_now()

    def delivered(self, uri: str, findings: Findings) -> None:
        """Note that the client has received ``findings`` (pulled them)."""
        # imported on first use (see ``_publish``)
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
            self._replaced.busy()
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
                elif not newer(d.snapshot.version, snap.version):
                    taken.append((d, snap))
                if snap.version == d.version:
                    published.append(findings_of(snap))
            self._publish(uri, published)
            # Requests see the new snapshots once their indexes are built (on the
            # analysis thread); until then the previous ones answer.
            oldest = self._replaced.oldest(len(taken))
            if snapshots or oldest:
                built = list(snapshots.values())
                try:
                    await loop.run_in_executor(self._executor, settle, built, oldest)
                except Exception:  # requests build what is missing
                    log.exception("preparing the snapshots of %s failed", uri)
            for d, snap in taken:
                if self.documents.get(d.uri) is d and d.snapshot is not None:
                    self._replaced.keep(d.snapshot)  # (a quiet spell may have renewed it)
                    d.replace_snapshot(snap)
            for d in batch:
                if d.uri in snapshots and self.documents.get(d.uri) is d:
                    self._wake(d)
            if self.options.verify and published and not doc.library:
                self._schedule_solver(uri)
            self._replaced.when_quiet()

    def _analyse(self, batch: list[Revision]) -> dict[str, Snapshot]:
        """Snapshots of the batch's texts (on the analysis thread)."""
        # imported on first use: the snapshot brings the analysis (136 ms measured after
        # osc2lsp.server), not needed to answer `initialize`
        from osc2lsp.snapshot import library_snapshot

        doc = batch[0]
        if doc.library:
            return {doc.uri: library_snapshot(doc.uri, doc.key, doc.text, doc.version)}
        config = self.configs.for_file(doc.key, self.options, self.root)
        with gc_paused():
            parses = {r.uri: p for r in batch if (p := r.parse()) is not None}
            found = analyse([(r.uri, r.text, r.version) for r in batch], config, False, parses)
            freeze()
        return found

    def _publish(self, trigger: str, findings: list[Findings]) -> None:
        """Hand findings the client does not have yet to the publisher."""
        # imported on first use: the feature brings the analysis (88 ms measured after
        # osc2lsp.server), not needed to answer `initialize`
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
        # imported on first use: the preview brings the analysis (157 ms measured after
        # osc2lsp.server), not needed to answer `initialize`
        from osc2lsp.session.preview import preview

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
            if doc.snapshot.version == doc.version or not newer(version, doc.snapshot.version):
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
            None, workspace_sources, Path(self.root), limit, open_keys, known, mentioning
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
