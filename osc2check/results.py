"""Stored results of whole checks: a check repeated on unchanged inputs is answered
from the start-up cache, the way ``ruff`` and ``mypy`` answer a repeated run.

The ``osc2check`` command starts here. When the same command line, in the same
folder, with the same ``OSC2_*`` variables and module path, was checked before and
nothing that check read has changed since, its output and exit status are given
again without importing the parser, the analysis or the solver. Otherwise the check
runs (``cli.main``) and, while it runs, everything it depends on is recorded:

* every file it opened for reading (an audit hook on ``open``: the sources, their
  imports, the configuration, maps, the standard library, plug-ins' files), as its
  size, modification and change times and inode (an edit changes the change time even
  when it keeps the size and sets the modification time back);
* every folder it listed (``os.scandir``, ``os.listdir``: the folders walked, those
  where installed plug-ins are looked for; not the module finder's), as its
  modification time, which a file added or removed changes;
* every file it looked for and did not find (``note_missing``: an import's earlier
  candidates, configuration files above the sources, a map file), which must still
  be absent;
* the code that ran: every module loaded, by its file.

The result is stored only when it can be given again as it was: exit status 0 or 1,
nothing on standard error, no file read from standard input, no finding that depends
on the machine's state (``not_repeatable``: a solver that ran out of time, a memory
budget exceeded), and no input modified within two seconds of the check (a
modification time that coarse clocks could not tell from the next edit's). An entry
is one ``result`` entry of :mod:`osc2check.cache` (atomic, checked, the user's own);
``--no-cache`` and ``OSC2_NO_CACHE=1`` neither read nor store one.
"""

from __future__ import annotations

import os
import sys
import time

TYPE_CHECKING = False  # typing's, without importing it: the command's first module
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any, NoReturn, TextIO

__all__ = [
    "check_here",
    "check_interruptible",
    "ignore_interrupts",
    "note_missing",
    "not_repeatable",
    "recorded",
    "recording",
    "repeatable",
    "run",
    "settled",
    "unchanged",
]

_KIND = "result"
_KEEP = 64  # stored results kept (the newest): one per command line and folder
_RACY_NS = 2_000_000_000  # an input modified this close to the check is not trusted
_MAX_OUTPUT = 2 * 1024 * 1024  # characters of output worth storing (64 entries: 128 Mi)
# options whose runs are never stored (argparse also takes any unambiguous beginning of one)
_NOT_STORED = ("--no-cache", "--debug", "--dump-ast", "--stdin-filename", "--help", "--version")
_COMMANDS = frozenset({"rule", "migrate"})
_SKIPPED_PREFIXES = ("/proc/", "/dev/", "/sys/")
_CODE_SUFFIXES = (".py", ".pyc", ".so", ".pyd")
_FINDER = "importlib._bootstrap_external"
# variables that do not change what a check prints (where it runs)
_SAME_OUTPUT = frozenset({"OSC2_RESIDENT", "OSC2_RESIDENT_IDLE"})

# size, modification and change times, inode; None: absent
Signature = tuple[int, int, int, int] | None
Dependencies = dict[str, Signature]


class _Recording:
    """What the running check depends on (see the module's docstring)."""

    def __init__(self, excluded: str) -> None:
        self.started = time.time_ns()
        self.files: Dependencies = {}
        self.folders: dict[str, int] = {}
        self.missing: set[str] = set()
        self.reasons: list[str] = []  # why the result cannot be given again
        self.excluded = excluded

    def audit(self, event: str, args: tuple[Any, ...]) -> None:
        if event == "open":
            path, mode, flags = args
            if isinstance(mode, str):
                writing = any(c in mode for c in "wax+")
            else:
                writing = bool(flags & (os.O_WRONLY | os.O_RDWR | os.O_CREAT))
            if not writing:
                self._file(path)
        elif event in ("os.scandir", "os.listdir"):
            self._folder(args[0])

    def _usable(self, path: object) -> str | None:
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        elif isinstance(path, os.PathLike):
            path = os.fspath(path)
        if not isinstance(path, str):
            return None  # a file descriptor: its file was recorded when it was opened
        path = os.path.abspath(path)
        if path.startswith(_SKIPPED_PREFIXES) or (path + os.sep).startswith(self.excluded):
            return None  # the cache's own files: their key says what they depend on
        return path

    def _file(self, path: object) -> None:
        usable = self._usable(path)
        if usable is not None and not usable.endswith(_CODE_SUFFIXES):
            if usable not in self.files:
                self.files[usable] = _signature(usable)

    def _folder(self, path: object) -> None:
        usable = self._usable("." if path is None else path)
        if usable is not None and usable not in self.folders:
            signature = _signature(usable)
            self.folders[usable] = signature[1] if signature is not None else -1

    def dependencies(self) -> Dependencies:
        """Everything recorded, modules included, as path -> signature."""
        found = dict(self.files)
        for module in list(sys.modules.values()):
            path = getattr(module, "__file__", None)
            if isinstance(path, str):
                path = os.path.abspath(path)
                if path not in found:
                    found[path] = _signature(path)
        for path in self.missing:
            found.setdefault(path, None)
        for folder, mtime in self.folders.items():
            found[folder + os.sep] = (0, mtime, 0, 0)
        return found


_recording: _Recording | None = None
_hooked = False


def note_missing(path: str | os.PathLike[str]) -> None:
    """Record that the check looked for ``path`` and found nothing there: a file created
    there later changes its result. A no-op unless a check is being recorded."""
    if _recording is not None:
        _recording.missing.add(os.path.abspath(os.fspath(path)))


def not_repeatable(reason: str) -> None:
    """Say that this check's result depends on more than its inputs (the machine's
    load, its memory): it is not stored."""
    if _recording is not None:
        _recording.reasons.append(reason)


def recording() -> bool:
    """Whether a check is being recorded (its result may be stored)."""
    return _recording is not None


def recorded() -> Dependencies:
    """What the check being recorded has depended on so far (``{}`` when none is)."""
    return _recording.dependencies() if _recording is not None else {}


def repeatable() -> bool:
    """Whether the check being recorded could still be given again (nothing it found
    depends on the machine's state so far); False when none is recorded."""
    return _recording is not None and not _recording.reasons


def settled(dependencies: Dependencies) -> bool:
    """Whether no file of ``dependencies`` was modified so close to the recorded check's
    start that a later edit could keep its signature."""
    if _recording is None:
        return False
    newest = max((s[1] for s in dependencies.values() if s is not None), default=0)
    return newest < _recording.started - _RACY_NS


def unchanged(dependencies: Dependencies) -> bool:
    """Whether every file and folder of ``dependencies`` still has its signature."""
    return _unchanged(dependencies)


def _audit(event: str, args: tuple[Any, ...]) -> None:
    if _recording is not None:
        if event == "os.listdir" and sys._getframe(1).f_globals.get("__name__") == _FINDER:
            return  # the module finder's listing: the modules it found are recorded
        _recording.audit(event, args)


def _signature(path: str) -> Signature:
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_ino)


def _folder_signature(path: str) -> Signature:
    signature = _signature(path)
    return (0, signature[1] if signature is not None else -1, 0, 0)


def _unchanged(dependencies: Dependencies) -> bool:
    for path, signature in dependencies.items():
        if path.endswith(os.sep):
            if _folder_signature(path[:-1]) != signature:
                return False
        elif _signature(path) != signature:
            return False
    return True


def _key(argv: list[str]) -> dict[str, str]:
    variables = sorted(
        (k, v) for k, v in os.environ.items() if k.startswith("OSC2") and k not in _SAME_OUTPUT
    )
    return {
        "argv": repr(argv),
        "cwd": os.getcwd(),
        "environment": repr(variables),
        "interpreter": sys.executable,
        "modules": repr(sys.path),  # where a plug-in named by the configuration is found
    }


def _storable(argv: list[str]) -> bool:
    """Whether the result of ``argv`` may be stored or given again at all."""
    if not argv or argv[0] in _COMMANDS:
        return False
    for arg in argv:
        if arg == "-" or arg.startswith("-h"):
            return False
        name = arg.partition("=")[0]
        if len(name) > 2 and name.startswith("--") and any(o.startswith(name) for o in _NOT_STORED):
            return False
    return True


class _Tee:
    """A text stream that writes through to ``stream`` and keeps what was written."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.parts: list[str] = []
        self.size = 0
        self.failed = False

    def write(self, text: str) -> int:
        try:
            written = self._stream.write(text)
        except BaseException:
            self.failed = True
            raise
        self.size += len(text)
        if self.size <= _MAX_OUTPUT:
            self.parts.append(text)
        return written

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _replay(argv: list[str]) -> tuple[str, int] | None:
    """The stored output and exit status of ``argv`` when nothing it read has changed."""
    from osc2check import cache

    found = cache.load(_KIND, _key(argv))
    if not isinstance(found, tuple) or len(found) != 3:
        return None
    dependencies, output, status = found
    if not _unchanged(dependencies):
        return None
    return output, status


def _record(argv: list[str], check: Callable[[list[str]], int]) -> int:
    """``check(argv)``, its result stored when it can be given again."""
    global _recording, _hooked
    from osc2check import cache

    recording = _Recording(os.path.join(os.path.abspath(cache.cache_folder()), ""))
    out, err = _Tee(sys.stdout), _Tee(sys.stderr)
    if not _hooked:
        sys.addaudithook(_audit)
        _hooked = True
    _recording = recording
    sys.stdout, sys.stderr = out, err
    try:
        status = check(argv)
    finally:
        sys.stdout, sys.stderr = out._stream, err._stream
        _recording = None
    if (
        status in (0, 1)
        and not recording.reasons
        and not out.failed
        and not err.size
        and out.size <= _MAX_OUTPUT
    ):
        dependencies = recording.dependencies()
        newest = max((s[1] for s in dependencies.values() if s is not None), default=0)
        if newest < recording.started - _RACY_NS:
            cache.store(_KIND, _key(argv), (dependencies, "".join(out.parts), status), keep=_KEEP)
    return status


def run() -> NoReturn:
    """The ``osc2check`` command: by the resident checker with ``OSC2_RESIDENT=1``
    (:mod:`osc2check.resident`), else here: the stored result when it still holds, else
    the check."""
    argv = sys.argv[1:]
    for name in ("stdout", "stderr"):  # closed when the process started (>&-): no output
        if getattr(sys, name) is None:
            setattr(sys, name, open(os.devnull, "w"))  # noqa: SIM115
    from osc2check.gc_pause import off_for_the_command

    off_for_the_command()
    if os.environ.get("OSC2_RESIDENT"):
        from osc2check import resident

        try:
            served = resident.request(argv) if resident.enabled() else None
        except KeyboardInterrupt:  # before the resident process had the check
            sys.stderr.write("osc2check: interrupted\n")
            _exit(130)
        if served is not None:
            _exit(served)
    _exit(check_interruptible(argv))


def check_interruptible(argv: list[str]) -> int:
    """:func:`check_here`; an interrupt (Ctrl-C) said in one line, exit status 130."""
    try:
        return check_here(argv)
    except KeyboardInterrupt:
        sys.stderr.write("osc2check: interrupted\n")
        return 130


def check_here(argv: list[str]) -> int:
    """Check ``argv`` in this process: its stored result when it still holds (written
    out), else the check, its result stored when it can be given again."""
    from osc2check import cache

    storable = _storable(argv) and cache.enabled()
    if storable:
        replayed = _replay(argv)
        if replayed is not None:
            output, status = replayed
            sys.stdout.write(output)
            return status
    from osc2check import cli

    return _record(argv, cli.main) if storable else cli.main(argv)


def ignore_interrupts() -> None:
    """Ctrl-C once the check has its answer: nothing left to stop (not a traceback from
    an exit handler it would fall in)."""
    import signal

    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread: nothing to do
        pass


def _exit(status: int) -> NoReturn:
    """Exit without freeing the process's objects one by one (the analysed library, the
    solver's context: about a quarter of a small file's check); the exit handlers run
    and the output is flushed first."""
    import atexit

    ignore_interrupts()
    run_handlers = getattr(atexit, "_run_exitfuncs", None)
    if run_handlers is None:  # pragma: no cover - a Python without it: the usual exit
        raise SystemExit(status)
    run_handlers()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a reader gone, a closed stream: nothing to say
            pass
    os._exit(status)
