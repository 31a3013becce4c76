"""Output files written whole or not at all, and the folder they go to.

Every file of a run (``telemetry.csv``, ``events.csv``, ``coverage.json``,
``run.json``, the plots) is written through this module:

* :func:`atomic_open` / :func:`write_atomically`: the content goes to a
  temporary file in the target's folder (``.NAME.XXXXXXXX.tmp``), which is
  flushed, ``fsync``-ed and renamed over ``NAME`` only once it is complete; on an
  exception the temporary file is removed and ``NAME`` is left as it was. A
  reader sees the old file or the new one, never a part of one. A process
  killed outright (SIGKILL, power loss) can leave a ``.*.tmp`` file behind,
  never a truncated ``NAME``.
* :func:`output_folder`: the folder exists and a file can be created in it, or
  it can be created (and is, unless asked not to), checked before anything runs.

::

    from osc2runner.output.files import atomic_open, write_atomically

    write_atomically(out / "coverage.json", json.dumps(doc, indent=2) + "\\n")
    with atomic_open(out / "telemetry.csv", "w", newline="") as f:
        f.write("actor,tick,...\\n")
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any, Literal

__all__ = ["FolderError", "atomic_open", "output_folder", "write_atomically"]

_TEMP_SUFFIX = ".tmp"


class FolderError(ValueError):
    """The output folder cannot be used: ``path`` and ``why`` (one short phrase)."""

    def __init__(self, path: str | os.PathLike[str], why: str) -> None:
        self.path = str(path)
        self.why = why
        super().__init__(f"{self.path}: {why}")


def _temporary(path: Path) -> tuple[Path, int]:
    """A new file beside ``path``, open for writing (mode 0o666 less the umask)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    while True:
        temp = path.with_name(f".{path.name}.{secrets.token_hex(4)}{_TEMP_SUFFIX}")
        try:
            return temp, os.open(temp, flags, 0o666)
        except FileExistsError:  # pragma: no cover - 32 random bits already taken
            continue


def _sync_folder(folder: Path) -> None:
    """Make a rename in ``folder`` durable (POSIX; a no-op where folders cannot be opened)."""
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # pragma: no cover - Windows
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - file systems that do not sync folders
        pass
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_open(
    path: str | os.PathLike[str],
    mode: Literal["w", "wb"] = "w",
    *,
    encoding: str = "utf-8",
    newline: str | None = None,
) -> Iterator[IO[Any]]:
    """Open ``path`` for writing, whole or not at all (see the module docstring).

    Parameters:
        path: the file to write; its folder must exist.
        mode: ``"w"`` (text, in ``encoding`` with ``newline`` as for :func:`open`) or
            ``"wb"`` (bytes).

    The file appears under ``path`` when the ``with`` block ends normally; if the
    block raises, ``path`` is untouched and the temporary file is removed.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open writes new files: mode 'w' or 'wb', not {mode!r}")
    target = Path(path)
    temp, fd = _temporary(target)
    try:
        if mode == "wb":
            f: IO[Any] = os.fdopen(fd, "wb")
        else:
            f = os.fdopen(fd, "w", encoding=encoding, newline=newline)
    except BaseException:  # pragma: no cover - fdopen failing on a valid descriptor
        os.close(fd)
        temp.unlink(missing_ok=True)
        raise
    try:
        with f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, target)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise
    _sync_folder(target.parent)


def write_atomically(
    path: str | os.PathLike[str], data: bytes | str, *, encoding: str = "utf-8"
) -> Path:
    """Write ``data`` (bytes, or text in ``encoding``, newlines as given) to ``path``,
    whole or not at all; returns the path."""
    target = Path(path)
    if isinstance(data, bytes):
        with atomic_open(target, "wb") as f:
            f.write(data)
    else:
        with atomic_open(target, "w", encoding=encoding, newline="") as f:
            f.write(data)
    return target


def output_folder(path: str | os.PathLike[str], *, create: bool = True) -> Path:
    """The folder ``path``, checked by creating a file in it; created when missing.

    With ``create=False`` a missing folder is not created: the nearest folder that
    exists above it is checked instead (the runner checks ``--out`` so before
    anything runs, and creates it when it writes the files: a run the checker
    rejects leaves nothing behind).

    Raises:
        FolderError: ``path`` is a file, lies under a file, cannot be created, or is
            not writable (a read-only folder or file system).
    """
    folder = Path(path)
    if folder.is_dir():
        _probe(path, folder, "the folder is not writable")
        return folder
    if folder.exists() or folder.is_symlink():
        raise FolderError(path, "is a file, not a folder")
    parent = next((p for p in folder.parents if p.exists() or p.is_symlink()), Path("."))
    if not parent.is_dir():
        raise FolderError(path, f"cannot create the folder: {parent} is not a folder")
    if not create:
        _probe(path, parent, f"cannot create the folder: {parent} is not writable")
        return folder
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FolderError(path, f"cannot create the folder: {_why(exc)}") from None
    _probe(path, folder, "the folder is not writable")
    return folder


def _probe(path: str | os.PathLike[str], folder: Path, why: str) -> None:
    """Create and remove a file in ``folder``; FolderError(path, why + the reason) if refused."""
    try:
        temp, fd = _temporary(folder / "write-test")
    except OSError as exc:
        raise FolderError(path, f"{why}: {_why(exc)}") from None
    os.close(fd)
    temp.unlink(missing_ok=True)


def _why(exc: OSError) -> str:
    return (exc.strerror or str(exc)).rstrip(".")
