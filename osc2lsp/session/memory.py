"""When the session's memory is freed and scanned: the memory policy.

A replaced snapshot is freed by reference counting (the checker's analyses hold
no reference cycles), on the analysis thread: freeing a 10,000-line document's
analysis holds the interpreter lock for a few tens of milliseconds, which a
request would wait for. So replaced snapshots are kept until the documents have
been quiet (no edit, no analysis) for ``QUIET_FREE`` seconds, a pause in
typing, and at most ``MAX_REPLACED`` of them: beyond that the oldest are freed
after the next analysis (``settle``). The collector is paused while an
analysis runs and what it made is frozen without a scan (``freeze``); every
generation is collected once the documents have been quiet for
``QUIET_COLLECTION`` seconds. The grammar and the library, loaded once at
start-up (``warm_up``), are frozen for good.
"""

from __future__ import annotations

import asyncio
import gc
import importlib
import logging
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any

from osc2check.gc_pause import gc_paused

if TYPE_CHECKING:
    from osc2lsp.snapshot import Snapshot

log = logging.getLogger(__name__)

# The interpreter lock passes between threads every SWITCH seconds (Python's default is
# 5 ms): a request waiting for the analysis thread to give it up waits that long, and
# it waits several times per request (reading, answering).
SWITCH = 0.001
QUIET_FREE = 0.5  # seconds without edits or analyses before replaced snapshots are freed
MAX_REPLACED = 3  # replaced snapshots kept until then, at most (about 13 MB each at 10,000 lines)
QUIET_COLLECTION = 30.0  # seconds without edits or analyses before a full collection


class Replaced:
    """The replaced snapshots kept until a quiet spell, and the wait for that spell."""

    def __init__(self, executor: ThreadPoolExecutor, tasks: set[asyncio.Task[Any]]) -> None:
        self._executor = executor  # the analysis thread: it frees them
        self._tasks = tasks  # the session's tasks (cancelled at shutdown)
        self.snapshots: list[Snapshot] = []
        self._quiet: asyncio.Task[None] | None = None  # what is done once all is quiet

    def busy(self) -> None:
        """Not quiet: an analysis starts."""
        if self._quiet is not None:
            self._quiet.cancel()

    def oldest(self, coming: int) -> list[Snapshot]:
        """Taken out: the oldest snapshots beyond ``MAX_REPLACED`` once ``coming`` more
        are kept (to be freed by ``settle`` after the analysis)."""
        replaced = self.snapshots
        oldest = replaced[: max(len(replaced) + coming - MAX_REPLACED, 0)]
        del replaced[: len(oldest)]
        return oldest

    def keep(self, snapshot: Snapshot) -> None:
        self.snapshots.append(snapshot)

    def when_quiet(self) -> None:
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
            if self.snapshots:
                freed, self.snapshots = self.snapshots, []
                await loop.run_in_executor(self._executor, freed.clear)
            await asyncio.sleep(QUIET_COLLECTION - QUIET_FREE)
            await loop.run_in_executor(self._executor, collect_all)

        self._quiet = task = loop.create_task(after_quiet())
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def free_now(self) -> None:
        """Free the replaced snapshots at once, as a quiet spell does."""
        if self.snapshots:
            freed, self.snapshots = self.snapshots, []
            await asyncio.get_running_loop().run_in_executor(self._executor, freed.clear)


def settle(snapshots: list[Snapshot], replaced: list[Snapshot]) -> None:
    """After an analysis, on its thread: ``replaced`` freed (it holds their last
    references) and what requests will need of ``snapshots`` built now."""
    replaced.clear()
    with gc_paused():
        for snap in snapshots:
            snap.prepare()
            warm_features(snap)
        freeze()


def freeze() -> None:
    """Exempt every object made so far from the collector's scans, without a scan.

    An analysis makes its objects with the collector paused; when the pause ended,
    the first allocation would start a collection that scans them all at once (tenths
    of a second on a 10,000-line document, holding the interpreter lock while a
    request waits). Analyses hold no reference cycles, so nothing is lost by not
    scanning them: a frozen object is still freed when its last reference goes.
    What cycles other code left meanwhile are collected when the documents are
    quiet (``collect_all``).
    """
    gc.freeze()


def collect_all() -> None:
    """Collect every generation, the frozen objects included, then freeze the survivors
    (after a quiet period: it holds the interpreter lock for tenths of a second)."""
    gc.unfreeze()
    gc.collect()
    gc.freeze()


def warm_features(snap: Snapshot) -> None:
    """Ask for a completion and a hover once, on the analysis thread: what they keep
    per snapshot (or load on first use) is then ready for the requests that follow."""
    # imported on first use: the features bring the analysis (168 ms measured after
    # osc2lsp.server), on this thread, not before `initialize` is answered
    from osc2lsp.features.completion import complete
    from osc2lsp.features.hover import hover

    try:
        complete(snap, snap.text, 0)
        names = snap.names
        if names:
            hover(snap, names[len(names) // 2].start)
    except Exception:  # the request itself will report it
        log.debug("warming the features failed", exc_info=True)


def warm_up() -> None:
    """Load the grammar and the library, then exempt them from garbage collection.

    It runs on the analysis thread from the moment the server starts, ahead of the
    first analysis (the client's `initialize` is answered meanwhile): ``gc.freeze``
    keeps whatever exists at that moment forever, and a document's analysis frozen
    by mistake would never be freed.
    """
    # imported here, on the analysis thread: the library, the grammar and the features
    # (168 ms measured after osc2lsp.server) would delay the answer to `initialize`
    from osc2check.semantics.stdlib import standard_library
    from osc2check.syntax.tables import parse_tables
    from osc2lsp.features.completion import complete

    parse_tables()
    standard_library()
    complete(None, "scenario s:\n    ", 16)  # the grammar table, the focus path
    importlib.import_module("osc2lsp.session.preview")  # what the first edit needs
    # the library and the grammar live as long as the process: never scan them. No
    # collection first: it finds a few dozen objects of garbage after all this (measured:
    # 54) and costs a full scan of the library, on the way to the first diagnostics
    gc.freeze()
