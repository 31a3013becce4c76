"""The memory budget of one file's check, and the element being analysed when it ran out.

``budget(limit)`` bounds the address space the check of one file may add to the
process (``RLIMIT_AS``, set to what the process maps now plus ``limit``, and put
back afterwards), so a file that would need more raises ``MemoryError`` (or makes
z3 answer "out of memory") instead of exhausting the machine. ``analysing(span,
what)`` records the element being analysed, so that the finding names it.

z3's own ``memory_max_size`` is not used: once z3 has hit it, every later context of
the process crashes (seen with z3 5.4.1), and one file must never cost the others
their check. The address-space limit covers z3's allocations as well; z3 turns a failed allocation
into an "out of memory" answer. A z3 context made without room crashes the process,
so ``room_for_solver`` checks for room first.
"""

from __future__ import annotations

import mmap
import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from osc2check.source import Span

#: a budget of at most this loads numpy before it (see ``analysis._load_once``)
PRELOAD_BELOW_MIB = 512
DEFAULT_MEMORY_LIMIT_MIB = 1024  # the bound: no input makes a tool use more than 1 GB
MIB = 1 << 20
# Address space a new z3 context needs free (it makes a few MiB of tables; 1 MiB of
# room crashed it, 30 MiB did not): ``room_for_solver`` asks for this much first.
SOLVER_ROOM = 48 * MIB


@dataclass(frozen=True, slots=True)
class Element:
    """What the check was analysing: its span and its description (``scenario `x```)."""

    span: Span
    what: str


class BudgetExceeded(MemoryError):
    """The check ran out of memory while analysing ``element``."""

    def __init__(self, element: Element):
        super().__init__(element.what)
        self.element = element


@contextmanager
def analysing(span: Span, what: str) -> Iterator[None]:
    """Run the block as the analysis of ``what`` at ``span``: running out of memory in
    it raises ``BudgetExceeded`` naming it (the innermost such block wins)."""
    try:
        yield
    except BudgetExceeded:
        raise
    except Exception as exc:
        if not is_out_of_memory(exc):
            raise
        raise BudgetExceeded(Element(span, what)) from None  # frees the failed frames


def _mapped() -> int | None:
    """Bytes of address space the process maps now (Linux), or None."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None


@contextmanager
def budget(limit_mib: int | None) -> Iterator[None]:
    """Let the block add at most ``limit_mib`` MiB to the process's address space.

    No budget with ``None`` or ``0``, or where the platform has no ``RLIMIT_AS``; a
    tighter limit the process already has is kept.
    """
    try:
        import resource
    except ImportError:  # pragma: no cover - not on POSIX
        yield
        return
    mapped = _mapped()
    if not limit_mib or mapped is None:
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    wanted = mapped + limit_mib * MIB
    if soft != resource.RLIM_INFINITY:
        wanted = min(wanted, soft)  # a tighter limit the user set (ulimit -v) stays
    resource.setrlimit(resource.RLIMIT_AS, (wanted, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def room_for_solver() -> None:
    """Raise ``MemoryError`` when the budget has no room for a new z3 context."""
    try:
        probe = mmap.mmap(-1, SOLVER_ROOM)  # address space only: no page is touched
    except OSError as exc:
        raise MemoryError("no room for a solver context") from exc
    probe.close()


OUT_OF_MEMORY = "out of memory"  # z3's reason (and error text) for a failed allocation


# the loader's words when a shared library finds no room (a module first imported under
# the budget: ``analysis`` imports those it knows of before, this catches the others)
_NO_ROOM_TO_LOAD = ("failed to map segment", "cannot allocate memory")


def is_out_of_memory(exc: BaseException) -> bool:
    """True for ``MemoryError``, for z3's error when an allocation failed, and for an
    import whose shared library could not be mapped."""
    if isinstance(exc, MemoryError):
        return True
    if isinstance(exc, ImportError):
        text = " ".join(str(e) for e in (exc, exc.__cause__, exc.__context__) if e).lower()
        return any(words in text for words in _NO_ROOM_TO_LOAD)
    return type(exc).__name__ == "Z3Exception" and OUT_OF_MEMORY in str(exc)
