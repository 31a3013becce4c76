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

Signal handlers can only be installed from the main thread: in another thread
:class:`Interrupts` installs nothing (:attr:`Interrupts.installed` is False)
and the run cannot be stopped by a signal; a ``progress`` callback that raises
``KeyboardInterrupt`` still stops it.

:func:`raising` is for the command around everything else: there SIGTERM and
SIGHUP, like SIGINT, raise :class:`SignalInterrupt` (a ``KeyboardInterrupt``),
so the command ends the same way whichever of them arrives.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType, TracebackType
from typing import Any

__all__ = ["SIGNALS", "Interrupts", "SignalInterrupt", "exit_status", "raising", "signal_name"]

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


class Interrupts:
    """The signals received while a run executes (see the module docstring).

    ``first`` is the first signal's number (None until one arrives); ``received``
    every signal in order. Use as a context manager; re-entering is an error.
    """

    def __init__(self, signals: tuple[int, ...] = SIGNALS) -> None:
        self.signals = signals
        self.first: int | None = None
        self.received: list[int] = []
        self.consumed = False
        self.installed = False
        self._previous: dict[int, Any] = {}

    def _note(self, signum: int, frame: FrameType | None) -> None:
        if self.first is None:
            self.first = signum
        self.received.append(signum)

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
        if not self.consumed and self.received and exc is None:
            signal.raise_signal(self.received[0])  # held while the files were written

    def _restore(self) -> None:
        for signum, handler in self._previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
        self._previous.clear()


class SignalInterrupt(KeyboardInterrupt):
    """SIGINT, SIGTERM or SIGHUP outside a run's loop (:func:`raising`); ``signum`` says which."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal_name(signum))
        self.signum = signum


def _raise(signum: int, frame: FrameType | None) -> None:
    raise SignalInterrupt(signum)


@contextlib.contextmanager
def raising(signals: tuple[int, ...] = SIGNALS) -> Iterator[None]:
    """Within the block, the ``signals`` raise :class:`SignalInterrupt` (main thread only;
    elsewhere a no-op); the previous handlers are restored after it."""
    if not _main_thread():
        yield
        return
    previous: dict[int, Any] = {}
    try:
        for signum in signals:
            previous[signum] = signal.signal(signum, _raise)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
