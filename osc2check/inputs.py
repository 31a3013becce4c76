"""Reading the files to check: what a path is, and its bytes, without ever blocking.

People and scripts hand the checker paths, and a path can be anything: a dangling or
looping symbolic link, a named pipe that blocks whoever opens it, a device that never
ends (``/dev/zero``), a file too large to be a scenario. Each of these becomes an
``InputProblem`` of that path, and every other file is still checked.

- The type of a path is decided with ``os.stat`` before it is opened, and only regular
  files are read. A FIFO, socket or device named on the command line cannot be read;
  met while walking a folder, it is skipped with a note.
- A file is opened with ``O_NONBLOCK`` (a path swapped for a FIFO between the ``stat``
  and the ``open`` still cannot block), checked again with ``fstat``, and read up to
  ``MAX_SOURCE_BYTES``: a larger file is a problem that says so, never a read without
  end.

The reasons are words for people (``broken symbolic link to `gone.osc```), written
after ``cannot read:`` by the command line.
"""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from osc2check import results
from osc2check.codes import Severity

__all__ = [
    "MAX_SOURCE_BYTES",
    "InputError",
    "InputProblem",
    "Met",
    "not_regular",
    "is_file",
    "probe",
    "read_bytes",
    "read_stream",
    "reason",
    "walk",
]

MAX_SOURCE_BYTES = 50 * 1024 * 1024  # far above any scenario; below what hurts to hold
_CHUNK = 1 << 20
_OPEN_FLAGS = (
    os.O_RDONLY
    | getattr(os, "O_NONBLOCK", 0)
    | getattr(os, "O_NOCTTY", 0)
    | getattr(os, "O_CLOEXEC", 0)
    | getattr(os, "O_BINARY", 0)
)
_REASONS = {
    errno.ENOENT: "no such file or directory",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.ELOOP: "symbolic link loop",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.ENAMETOOLONG: "file name too long",
    errno.EISDIR: "a folder, not a file",
}


class InputError(Exception):
    """Why a path cannot be read, in words (``permission denied``)."""


@dataclass(frozen=True, slots=True)
class InputProblem:
    """A path that was not checked, and why.

    An error (``cannot read: ...``) makes the exit status 2; a note (``skipped: ...``)
    tells of a special file left out of a folder walk and changes nothing else.
    """

    path: str  # as the output names files
    message: str
    severity: Severity = Severity.ERROR

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR


def reason(exc: OSError, path: str | Path | None = None) -> str:
    """``exc`` in words; a missing ``path`` that is a link is named a broken link."""
    if exc.errno == errno.ENOENT and path is not None:
        try:
            target = os.readlink(path)
        except OSError:
            pass
        else:
            return f"broken symbolic link to `{target}`"
    known = _REASONS.get(exc.errno or 0)
    if known:
        return known
    text = exc.strerror or str(exc)
    return text[:1].lower() + text[1:]


def probe(path: str | Path) -> os.stat_result:
    """The status of ``path``, symbolic links followed; ``InputError`` says why not."""
    try:
        return os.stat(path)
    except OSError as exc:
        if isinstance(exc, (FileNotFoundError, NotADirectoryError)):
            results.note_missing(path)
        raise InputError(reason(exc, path)) from None
    except ValueError:  # a NUL byte in the name
        raise InputError("invalid file name") from None


def is_file(path: str | Path) -> bool:
    """Whether ``path`` is a regular file (links followed); a miss is noted, since a file
    made there later changes what a check finds (``results.note_missing``)."""
    if os.path.isfile(path):
        return True
    results.note_missing(path)
    return False


@dataclass(frozen=True, slots=True)
class Met:
    """A path met walking a folder: a source to read (``why`` None), or why not."""

    path: Path
    why: str | None = None
    error: bool = False  # it cannot be read (else a special file, skipped with a note)


def walk(root: Path, excluded: Callable[[Path], bool] | None = None) -> Iterator[Met]:
    """The ``*.osc`` paths below ``root``, in sorted order, each with why it is not read.

    A regular file (links followed) is a source; a FIFO, socket or device named
    ``*.osc`` is skipped (a note: it is never opened); a link that leads nowhere and a
    folder that cannot be listed cannot be read (errors). Links to folders are not
    followed; folders and files ``excluded`` says are left out. The command line and
    the language server's workspace search both walk this way.
    """
    met: list[Met] = []  # folders that cannot be listed, met while walking

    def unlisted(exc: OSError) -> None:
        met.append(Met(Path(exc.filename) if exc.filename else root, reason(exc), True))

    for dirpath, dirnames, filenames in os.walk(root, onerror=unlisted):
        yield from met
        met.clear()
        here = Path(dirpath)
        dirnames[:] = sorted(d for d in dirnames if not (excluded and excluded(here / d)))
        for name in sorted(filenames):
            path = here / name
            if not name.endswith(".osc") or (excluded and excluded(path)):
                continue
            try:
                why = not_regular(probe(path))
            except InputError as exc:
                yield Met(path, str(exc), True)
                continue
            yield Met(path, why)
    yield from met


def not_regular(status: os.stat_result) -> str | None:
    """Why a path with ``status`` is not read as a source, or None for a regular file."""
    mode = status.st_mode
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a folder, not a file"
    for test, kind in (
        (stat.S_ISFIFO, "a named pipe"),
        (stat.S_ISSOCK, "a socket"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
    ):
        if test(mode):
            return f"not a regular file ({kind})"
    return "not a regular file"


def _mib(size: int) -> str:
    """``50 MiB`` for a whole number of MiB, else the bytes (``40 bytes``)."""
    mib, rest = divmod(size, 1024 * 1024)
    return f"{mib} MiB" if mib and not rest else f"{size:,} bytes"


def _too_large(size: int | None, limit: int) -> str:
    if size is None:
        return f"too large (more than the limit of {_mib(limit)})"
    return f"too large ({size:,} bytes; the limit is {_mib(limit)})"


def read_bytes(path: str | Path, limit: int | None = None) -> bytes:
    """The bytes of the regular file ``path``, at most ``limit`` (``MAX_SOURCE_BYTES``).

    Never blocks and never reads more than ``limit + 1`` bytes; raises ``InputError``
    for anything else than a readable regular file of at most ``limit`` bytes.
    """
    limit = MAX_SOURCE_BYTES if limit is None else limit
    status = probe(path)
    why = not_regular(status)
    if why:
        raise InputError(why)
    if status.st_size > limit:
        raise InputError(_too_large(status.st_size, limit))
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except OSError as exc:
        raise InputError(reason(exc, path)) from None
    try:
        why = not_regular(os.fstat(fd))  # the path may have changed since the stat
        if why:
            raise InputError(why)
        return _read_capped(lambda n: os.read(fd, n), limit)  # the file may grow after the stat
    except OSError as exc:
        raise InputError(reason(exc)) from None
    finally:
        os.close(fd)


def read_stream(stream: BinaryIO, limit: int | None = None) -> bytes:
    """All of ``stream`` (standard input), at most ``limit`` bytes, else ``InputError``."""
    return _read_capped(stream.read, MAX_SOURCE_BYTES if limit is None else limit)


def _read_capped(read: Callable[[int], bytes], limit: int) -> bytes:
    """What ``read`` gives until it is exhausted, at most ``limit`` bytes, else
    ``InputError`` (so is an ``OSError`` of the read)."""
    chunks: list[bytes] = []
    size = 0
    try:
        while size <= limit:
            chunk = read(min(_CHUNK, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise InputError(reason(exc)) from None
    if size > limit:
        raise InputError(_too_large(None, limit))
    return b"".join(chunks)
