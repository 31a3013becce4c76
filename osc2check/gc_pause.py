"""Pausing Python's cyclic garbage collector around work that only builds.

Parsing and analysis make hundreds of thousands of objects that live as long as
their result and free almost none: collections during them scan a growing heap
for nothing. ``gc.disable()`` and ``gc.enable()`` act on the whole process, so
two threads that each switched the collector off and back on could undo each
other: one thread's ``enable`` would turn it on in the middle of the other's
analysis, and a thread that found it already off (paused by the other) would
leave it as it found it. ``gc_paused`` counts the pauses instead: the first to
begin switches the collector off (if it was on), the last to end switches it
back on (if it was on when the first began).

Code that calls ``gc.enable()`` itself while a pause runs is not prevented from
doing so; nothing in the toolkit does.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator
from contextlib import contextmanager

_lock = threading.RLock()
_pauses = 0  # pauses now running, in all threads
_resume = False  # the collector was on when the first of them began


@contextmanager
def gc_paused() -> Iterator[None]:
    """Run the body with the cyclic garbage collector off (thread-safe, nestable)."""
    global _pauses, _resume
    with _lock:
        if _pauses == 0:
            _resume = gc.isenabled()
            gc.disable()
        _pauses += 1
    try:
        yield
    finally:
        with _lock:
            _pauses -= 1
            if _pauses == 0 and _resume:
                gc.enable()


def pauses() -> int:
    """How many pauses are running now (for tests)."""
    with _lock:
        return _pauses


def off_for_the_command() -> None:
    """Switch the collector off for the rest of a process that ends with its command (the
    ``osc2check`` command, a resident checker's child), as mypy does for its own.

    The analysis pauses it anyway (``gc_paused``); what this adds is the time before and
    after: reading the cache (a large file's last parse and the analysed library,
    hundreds of thousands of objects) and writing the findings and the cache, during
    which each collection scans all of them to free next to nothing. Memory held is
    what the analysis holds: the process ends with ``os._exit`` and frees nothing one by
    one either."""
    gc.disable()
