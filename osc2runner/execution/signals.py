"""SIGINT, SIGTERM and SIGHUP during a run: stop at the end of the tick, write, then exit.

:class:`Interrupts` is the context a run executes in (``runner.execute``):

* while it is active, SIGINT, SIGTERM and SIGHUP (where the platform has it)
  only note the signal: the tick loop reads :attr:`Interrupts.first` between
  ticks and ends the run as ``interrupted`` — a tick is never cut in half, so
  the telemetry ends at a tick boundary;
* the files are written while it is still active, so no further signal can cut
  a write short;
* on leaving, the handlers in place before are restored. A signal that did
  not stop the loop (one that arrived after the run had ended on its own,
  while its files were written) is then delivered to them: with Python's
  defaults SIGINT raises ``KeyboardInterrupt`` and SIGTERM ends the process.
  Signals after the one that stopped the loop ask for what is happening
  already and are dropped.

Code the run calls but does not control, a system under test's, may never come
back to the loop (it sleeps, it loops, it swallows every exception). So
:func:`foreign_code` marks it: there a signal raises :class:`SignalInterrupt` at
once, and the code has a wall-clock budget (SIGALRM raises :class:`StepTimeout`,
which ``except Exception`` does not catch). What such code does with either is
not trusted: a second signal, or the budget running out a second time, makes a
*hard stop* when the run has one (``Interrupts(hard_stop=...)``, the command's
runs): the files are written from the handler with the outcome so far and the
process ends (:func:`exit_status`; 2 for the budget). Outside foreign code a
second signal before the loop has stopped raises :class:`SignalInterrupt` too:
whatever our code was doing, the run stops there.

Signal handlers can only be installed from the main thread: in another thread
:class:`Interrupts` installs nothing (:attr:`Interrupts.installed` is False)
and the run cannot be stopped by a signal (nor is foreign code timed); a
``progress`` callback that raises ``KeyboardInterrupt`` still stops it.

:func:`raising` is for the command around everything else: there SIGTERM and
SIGHUP, like SIGINT, raise :class:`SignalInterrupt` (a ``KeyboardInterrupt``),
so the command ends the same way whichever of them arrives; a second signal
ends the process at once (what was interrupted may have swallowed the first).
It records the signals it saw (:attr:`Caught.first`): an import interrupted
half-way fails with some other exception (``ImportError: initialization
failed``), which is still an interruption.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType, TracebackType
from typing import Any

from osc2runner.execution.outcome import OutcomeStatus

__all__ = [
    "SIGNALS",
    "Caught",
    "Interrupts",
    "SignalInterrupt",
    "StepTimeout",
    "exit_status",
    "foreign_code",
    "genuine",
    "raising",
    "signal_name",
]

#: seconds after a budget ran out before it is taken to have run out a second time
OVERRUN_GRACE = 2.0
#: ``hard_stop(status, reason, signum)``: write the files with this outcome, end the process
HardStop = Callable[[OutcomeStatus, str, "int | None"], None]

#: the signals that interrupt a run: SIGINT, SIGTERM, and SIGHUP where it exists
SIGNALS: tuple[int, ...] = tuple(
    int(getattr(signal, name)) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


def signal_name(signum: int) -> str:
    """``SIGTERM`` for 15 (the number as text for a signal without a name)."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return str(signum)


def exit_status(signum: int | None) -> int:
    """The exit status of a run stopped by ``signum``: 128 + its number, as a shell reports
    a process ended by it (130 SIGINT, 143 SIGTERM, 129 SIGHUP); 130 without a signal."""
    return 128 + (int(signal.SIGINT) if signum is None else signum)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


class SignalInterrupt(KeyboardInterrupt):
    """A signal turned into an exception where the code was (``signum`` says which)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal_name(signum))
        self.signum = signum


class StepTimeout(BaseException):
    """Foreign code ran past its wall-clock budget (raised into it by SIGALRM)."""


_raised: list[BaseException] = []  # what a handler raised last: the genuine article


def _throw(exc: BaseException) -> None:
    _raised[:] = [exc]
    raise exc


def genuine(exc: BaseException) -> bool:
    """Whether ``exc`` was raised by a handler here, not made up by foreign code."""
    return bool(_raised) and _raised[0] is exc


_active: list[Interrupts] = []  # the run executing now, if any


class Interrupts:
    """The signals received while a run executes (see the module docstring).

    ``first`` is the first signal's number (None until one arrives); ``received``
    every signal in order. ``hard_stop`` ends the process with the files written
    when foreign code does not stop. Use as a context manager; re-entering is an error.
    """

    def __init__(self, signals: tuple[int, ...] = SIGNALS, hard_stop: HardStop | None = None):
        self.signals = signals
        self.first: int | None = None
        self.received: list[int] = []
        self.consumed = False
        self.writing = False  # the files are being written: nothing may cut them
        self.installed = False
        self.hard_stop = hard_stop
        self.foreign = 0  # depth of foreign code running now
        self._previous: dict[int, Any] = {}

    def _note(self, signum: int, frame: FrameType | None) -> None:
        if self.first is None:
            self.first = signum
        self.received.append(signum)
        if self.consumed or self.writing:
            return  # the loop has stopped: the files are being written
        if self.foreign:  # code that may never come back: stop it where it is
            if len(self.received) > 1 and self.hard_stop is not None:
                self.hard_stop("interrupted", f"interrupted by {signal_name(signum)}", signum)
            _throw(SignalInterrupt(signum))
        if len(self.received) > 1:  # the loop did not stop for the first: stop here
            _throw(SignalInterrupt(signum))

    def consume(self) -> int | None:
        """Called by the loop when it stops for :attr:`first`: later signals are dropped."""
        self.consumed = True
        return self.first

    def __enter__(self) -> Interrupts:
        if self._previous:
            raise RuntimeError("Interrupts is already active")
        if not _main_thread():
            return self
        try:
            for signum in self.signals:
                self._previous[signum] = signal.signal(signum, self._note)
        except BaseException:
            self._restore()
            raise
        self.installed = True
        _active.append(self)
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if not self.installed:
            return
        self._restore()
        self.installed = False
        if self in _active:
            _active.remove(self)
        if not self.consumed and self.received and exc is None:
            signal.raise_signal(self.received[0])  # held while the files were written

    def _restore(self) -> None:
        for signum, handler in self._previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
        self._previous.clear()


class Caught:
    """The signals :func:`raising` turned into exceptions (``first``: None until one came)."""

    def __init__(self) -> None:
        self.received: list[int] = []

    @property
    def first(self) -> int | None:
        return self.received[0] if self.received else None

    def _raise(self, signum: int, frame: FrameType | None) -> None:
        self.received.append(signum)
        if len(self.received) > 1:  # the first was swallowed where it was raised
            sys.stderr.write(f"osc2run: interrupted by {signal_name(signum)} again: stopping\n")
            sys.stderr.flush()
            os._exit(exit_status(signum))
        _throw(SignalInterrupt(signum))


@contextlib.contextmanager
def raising(signals: tuple[int, ...] = SIGNALS) -> Iterator[Caught]:
    """Within the block, the ``signals`` raise :class:`SignalInterrupt` (main thread only;
    elsewhere a no-op), and a second one ends the process; the previous handlers are
    restored after it. Yields what it caught."""
    caught = Caught()
    if not _main_thread():
        yield caught
        return
    previous: dict[int, Any] = {}
    try:
        for signum in signals:
            previous[signum] = signal.signal(signum, caught._raise)
        yield caught
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)


@contextlib.contextmanager
def foreign_code(budget: float | None, what: str = "foreign code") -> Iterator[list[bool]]:
    """Run code the run does not control (see the module docstring) with ``budget``
    wall-clock seconds (None: no limit); ``what`` names it for a hard stop. Yields a
    flag set once the budget ran out (the code may have caught :class:`StepTimeout`
    and returned all the same)."""
    expired = [False]
    run = _active[-1] if _active else None
    timed = budget is not None and _main_thread() and hasattr(signal, "setitimer")

    def overrun(signum: int, frame: FrameType | None) -> None:
        first = not expired[0]
        expired[0] = True
        if not first and run is not None and run.hard_stop is not None:
            run.hard_stop("error", f"{what} ran past {budget:g} s and did not stop", None)
        _throw(StepTimeout(f"{budget:g} s"))

    previous: Any = None
    if timed and budget is not None:
        previous = signal.signal(signal.SIGALRM, overrun)
        signal.setitimer(signal.ITIMER_REAL, budget, OVERRUN_GRACE)
    if run is not None:
        run.foreign += 1
    try:
        yield expired
    finally:
        if run is not None:
            run.foreign -= 1
        if timed:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous if previous is not None else signal.SIG_DFL)
