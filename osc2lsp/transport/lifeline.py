"""Processes that end with the process they serve.

A killed language server must not leave its solver worker behind (nor, as
with ``multiprocessing``, a resource tracker waiting for that worker), and a
server whose editor is gone must stop too. Three mechanisms, each a fallback
for the one before:

* on Linux, ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: the kernel kills the child
  the moment its parent dies, even by SIGKILL, even while the child is deep
  in a z3 call;
* everywhere, a daemon thread that polls whether the parent is still there
  (``os.getppid()`` changes when a POSIX process is re-parented; on Windows
  the parent's handle is asked);
* the pipe the parent writes requests into reaches end-of-file (the worker's
  main loop returns).
"""

from __future__ import annotations

import ctypes
import logging
import os
import signal
import sys
import threading
from collections.abc import Callable

log = logging.getLogger(__name__)

_PR_SET_PDEATHSIG = 1
_POLL_SECONDS = 0.5


def die_with_parent(parent: int, poll: float = _POLL_SECONDS) -> None:
    """End this process (``os._exit``) when process ``parent`` ends."""
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
                log.debug("prctl(PR_SET_PDEATHSIG) failed: errno %d", ctypes.get_errno())
        except (OSError, AttributeError):  # no libc symbol: the poll below still works
            pass
    if _parent_gone(parent):  # it ended before the kernel was told to watch it
        os._exit(1)
    watch(lambda: _parent_gone(parent), lambda: os._exit(1), poll, "osc2lsp-parent-watch")


def watch(
    gone: Callable[[], bool], then: Callable[[], None], poll: float, name: str
) -> threading.Thread:
    """Call ``then()`` once ``gone()`` is true, checking every ``poll`` seconds."""
    stop = threading.Event()

    def loop() -> None:
        while not stop.wait(poll):
            if gone():
                then()
                return

    thread = threading.Thread(target=loop, name=name, daemon=True)
    thread.start()
    return thread


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists (never signals it)."""
    if pid <= 0:
        return False
    if sys.platform == "win32":
        return _windows_alive(pid)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # it exists, under another user
        return True
    return True


def _parent_gone(parent: int) -> bool:
    if sys.platform == "win32":
        return not _windows_alive(parent)
    return os.getppid() != parent


def _windows_alive(pid: int) -> bool:  # pragma: no cover - Windows only
    kernel32 = ctypes.windll.kernel32  # type: ignore[attr-defined]
    synchronize, still_active = 0x00100000 | 0x1000, 259
    handle = kernel32.OpenProcess(synchronize, False, pid)
    if not handle:
        return False
    try:
        code = ctypes.c_ulong()
        if not kernel32.GetExitCodeProcess(handle, ctypes.byref(code)):
            return True
        return code.value == still_active
    finally:
        kernel32.CloseHandle(handle)
