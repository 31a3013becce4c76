"""Open documents, their snapshots, and when they are analysed.

Each edit (re)starts a short debounce timer for its document; when it runs
out, the document is analysed together with the open documents that import
it (their findings may change) and the open documents it imports (so their
unsaved text is used). A newer edit cancels a timer that has not run out and
makes any analysis still running stale: its snapshots are kept (they are the
best ones available while typing) but only the current version's findings
are published. Analyses run one at a time on a worker thread, so the event
loop keeps answering requests meanwhile.

Analysis has two phases. The first (syntax, names, types, units, arguments)
is fast and runs after every edit. The second adds the solver's checks
(constraints, placement, behaviour flow: z3 for every scenario), which can
take seconds on a large file; it runs on its own worker once the document
has been quiet for ``verify_delay`` milliseconds, and its findings replace
the first phase's when no newer edit came meanwhile. It runs in a separate
process (the first one, once per server), so the solver never competes with
the analysis of the next keystroke for the interpreter lock, and it only
sends back the findings.

Requests that must see the current text (hover, definition, rename, pulled
diagnostics...) await ``fresh(uri)``, which skips the rest of the debounce.
Completion and signature help use ``latest(uri)`` and the current text.
"""

from __future__ import annotations

import asyncio
import logging
import multiprocessing
import os
import re
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from osc2lsp.options import CheckerConfigs, Options
from osc2lsp.text import LineIndex, uri_to_key

if TYPE_CHECKING:
    from osc2lsp.snapshot import Snapshot

log = logging.getLogger(__name__)


def solver_findings(documents: list[tuple[str, str]], config=None) -> dict[str, list]:
    """The full findings, solver included, of documents given as ``(key, text)``.

    Runs in the solver process: only the findings (plain, picklable data) come back.
    """
    from osc2check.analysis import SourceInput, analyze
    from osc2check.config import Config

    options = (config if config is not None else Config()).analysis_options()
    analysis = analyze([SourceInput(key, text) for key, text in documents], options)
    found: dict[str, list] = {key: [] for key, _ in documents}
    for d in analysis.diagnostics:
        if d.span.uri in found:
            found[d.span.uri].append(d)
    return found


def _portable(config):
    """The configuration with plain dicts, so that it can be sent to another process."""
    if config is None:
        return None
    from dataclasses import fields, replace

    changes = {
        f.name: dict(getattr(config, f.name))
        for f in fields(config)
        if isinstance(getattr(config, f.name), MappingProxyType)
    }
    return replace(config, **changes) if changes else config


def analyse(
    documents: list[tuple[str, str, int | None]], config=None, verify: bool = True
) -> dict[str, Snapshot]:
    """Analyse documents given as ``(uri, text, version)``; a snapshot for each.

    Without ``verify`` the solver's checks (C, L and B codes) are left out.
    """
    from osc2check.analysis import SourceInput, analyze  # heavy: imported on first use
    from osc2check.config import Config
    from osc2lsp.snapshot import Snapshot

    keys = {uri: uri_to_key(uri) for uri, _, _ in documents}
    inputs = [SourceInput(keys[uri], text) for uri, text, _ in documents]
    config = config if config is not None else Config()
    analysis = analyze(inputs, config.analysis_options(verify=verify))
    return {
        uri: Snapshot(uri, keys[uri], version, text, analysis, config, verify)
        for uri, text, version in documents
    }


def snapshot_of(
    text: str, uri: str = "file:///tmp/osc2lsp/document.osc", version: int | None = 1, config=None
) -> Snapshot:
    """A snapshot of one text (for tests and scripts)."""
    return analyse([(uri, text, version)], config)[uri]


@dataclass(eq=False)
class Document:
    uri: str
    text: str
    version: int | None
    key: str = ""
    snapshot: Snapshot | None = None  # the latest analysis, maybe of an older version
    timer: asyncio.Task | None = None  # the debounce, until the analysis starts
    verify_timer: asyncio.Task | None = None  # the quiet period before the solver runs
    waiters: list[tuple[int | None, asyncio.Future]] = field(default_factory=list)
    stale: bool = False  # a file it imports changed since its snapshot was made
    _lines: LineIndex | None = field(default=None, repr=False)

    def __post_init__(self):
        self.key = self.key or uri_to_key(self.uri)

    @property
    def lines(self) -> LineIndex:
        """The line index of the current text (computed once per text)."""
        if self._lines is None or self._lines.text is not self.text:
            self._lines = LineIndex(self.text)
        return self._lines

    @property
    def current(self) -> bool:
        return (
            self.snapshot is not None and self.snapshot.version == self.version and not self.stale
        )


Publisher = Callable[[str, list["Snapshot"]], None]


class State:
    """The open documents and their analysis schedule."""

    def __init__(
        self,
        options: Options | None = None,
        publish: Publisher | None = None,
        root: str | None = None,
    ):
        self.options = options or Options()
        self.publish = publish or (lambda trigger, snapshots: None)
        self.root = root
        self.documents: dict[str, Document] = {}
        self.configs = CheckerConfigs()
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="osc2-analysis")
        self._solver: ProcessPoolExecutor | None = None
        self._closed: dict[str, tuple[float, str, Snapshot | None]] = {}  # workspace files
        self._lock: asyncio.Lock | None = None
        self._tasks: set[asyncio.Task] = set()

    # ---- documents -------------------------------------------------------------

    def open(self, uri: str, text: str, version: int | None) -> None:
        self.documents[uri] = Document(uri, text, version)
        self.schedule(uri, 0)

    def change(self, uri: str, text: str, version: int | None) -> None:
        doc = self.documents.get(uri)
        if doc is None:
            self.open(uri, text, version)
            return
        doc.text, doc.version = text, version
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
        if timer is None or timer.done() or getattr(timer, "sleeping", False):
            self.schedule(uri, 0)  # skip the rest of the debounce (a running one will do)
        return await future

    async def fresh_all(self) -> list[Snapshot]:
        """The snapshots of the current versions of every open document."""
        snapshots = [await self.fresh(uri) for uri in list(self.documents)]
        return [s for s in snapshots if s is not None]

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
        if doc.timer is not None and not doc.timer.done() and getattr(doc.timer, "sleeping", False):
            doc.timer.cancel()
        delay = self.options.debounce if delay_ms is None else delay_ms
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return
        task = loop.create_task(self._run(uri, delay / 1000))
        task.sleeping = True  # type: ignore[attr-defined]
        doc.timer = task
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _run(self, uri: str, delay: float) -> None:
        task = asyncio.current_task()
        if delay > 0:
            await asyncio.sleep(delay)
        if self._lock is None:
            self._lock = asyncio.Lock()
        async with self._lock:
            task.sleeping = False  # type: ignore[attr-defined]
            doc = self.documents.get(uri)
            if doc is None or doc.current:
                self._wake(doc)
                return
            batch = self._batch(doc)
            for member in batch:
                member.stale = False
            config = self.configs.for_file(doc.key, self.options, self.root)
            inputs = [(d.uri, d.text, d.version) for d in batch]
            loop = asyncio.get_running_loop()
            verify = self.options.verify
            try:
                snapshots = await loop.run_in_executor(
                    self._executor, analyse, inputs, config, False
                )
            except Exception:  # an internal error of the checker: keep serving
                log.exception("analysis of %s failed", uri)
                snapshots = {}
            published: list[Snapshot] = []
            for d in batch:
                snap = snapshots.get(d.uri)
                current = self.documents.get(d.uri)
                if snap is None or current is not d:
                    continue
                if d.snapshot is None or not _newer(d.snapshot.version, snap.version):
                    d.snapshot = snap
                if snap.version == d.version:
                    published.append(snap)
                self._wake(d)
            self._publish(uri, published)
            if verify and published:
                self._schedule_solver(uri)

    def _publish(self, trigger: str, snapshots: list[Snapshot]) -> None:
        if not snapshots:
            return
        try:
            self.publish(trigger, snapshots)
        except Exception:
            log.exception("publishing diagnostics failed")

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

    def solver(self) -> ProcessPoolExecutor:
        """The solver process (started on first use; `spawn`, since this process has
        threads)."""
        if self._solver is None:
            self._solver = ProcessPoolExecutor(
                max_workers=1, mp_context=multiprocessing.get_context("spawn")
            )
        return self._solver

    async def _solve(self, uri: str, delay: float) -> None:
        """The findings of the solver's checks for a document that has been quiet."""
        if delay > 0:
            await asyncio.sleep(delay)
        doc = self.documents.get(uri)
        if doc is None or not doc.current:
            return  # a newer edit is on its way; its analysis schedules this again
        batch = self._batch(doc)
        versions = {d.uri: (d.version, d.text) for d in batch}
        config = _portable(self.configs.for_file(doc.key, self.options, self.root))
        inputs = [(d.key, d.text) for d in batch]
        loop = asyncio.get_running_loop()
        try:
            found = await loop.run_in_executor(self.solver(), solver_findings, inputs, config)
        except Exception:
            log.exception("solver checks of %s failed", uri)
            if self._solver is not None:
                self._solver.shutdown(wait=False, cancel_futures=True)
                self._solver = None
            return
        published = []
        for d in batch:
            if self.documents.get(d.uri) is not d or d.stale or not d.current:
                continue
            if (d.version, d.text) == versions[d.uri] and d.key in found:
                d.snapshot = d.snapshot.with_findings(found[d.key])
                published.append(d.snapshot)
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
        by_key = {d.key: d for d in self.documents.values()}
        for other in self.documents.values():
            snap = other.snapshot
            if (
                other is not doc
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
        contains ``mentioning`` (references and rename reach into them)."""
        if not self.root or not Path(self.root).is_dir():
            return []
        open_keys = {d.key for d in self.documents.values()}
        loop = asyncio.get_running_loop()
        found: list[Snapshot] = []
        for path in _osc_files(Path(self.root), limit):
            key = str(path)
            if key in open_keys:
                continue
            try:
                stat = path.stat()
                cached = self._closed.get(key)
                if cached is None or cached[0] != stat.st_mtime:
                    text = path.read_text(encoding="utf-8", errors="replace")
                    cached = self._closed[key] = (stat.st_mtime, text, None)
            except OSError:
                continue
            mtime, text, snap = cached
            if not re.search(rf"(?<!\w){re.escape(mentioning)}(?!\w)", text):
                continue
            if snap is None:
                config = self.configs.for_file(key, self.options, self.root)
                uri = path.as_uri()
                snap = (
                    await loop.run_in_executor(
                        self._executor, analyse, [(uri, text, None)], config, False
                    )
                )[uri]
                self._closed[key] = (mtime, text, snap)
            found.append(snap)
        return found

    async def shutdown(self) -> None:
        """Cancel the timers and stop the workers (a running solver job is killed)."""
        for task in list(self._tasks):
            task.cancel()
        self._executor.shutdown(wait=False, cancel_futures=True)
        if self._solver is not None:
            processes = list(getattr(self._solver, "_processes", {}).values())
            self._solver.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                process.terminate()
            self._solver = None


def _osc_files(root: Path, limit: int):
    """The `.osc` files under ``root``, skipping the folders ``osc2check`` skips and
    the bundled library."""
    from osc2check.config import DEFAULT_EXCLUDE
    from osc2check.resources import stdlib_dir

    library = stdlib_dir().resolve()
    count = 0
    for folder, dirs, files in os.walk(root):
        if Path(folder).resolve() == library:
            dirs[:] = []
            continue
        dirs[:] = sorted(d for d in dirs if d not in DEFAULT_EXCLUDE and not d.startswith("."))
        for name in sorted(files):
            if name.endswith(".osc"):
                yield Path(folder) / name
                count += 1
                if count >= limit:
                    return


def _newer(a: int | None, b: int | None) -> bool:
    if a is None or b is None:
        return True
    return a > b
