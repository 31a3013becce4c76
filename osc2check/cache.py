"""The start-up cache: fixed work that every process would redo, kept on disk.

What a checker, a language server or a runner process needs before it reads the
user's first file does not depend on that file: the parser's tables (from the
grammar) and the analysed standard library. They are built once and kept here,
each entry keyed by everything its value depends on:

* ``toolkit``: the toolkit's code, as the size and modification time of every
  module of ``osc2check`` (a new version, an edited checkout, a reinstall all
  change it), and ``format``, this module's file layout;
* ``python``: the interpreter's version and implementation;
* what the caller adds: the grammar's or the library's text, the lark version, and
  anything that later changes an analysis (a selected OSC2 version: one more
  field in the caller's ``key``).

Where: ``OSC2_CACHE_DIR`` when set, else the user's cache folder
(``$XDG_CACHE_HOME/osc2`` or ``~/.cache/osc2``; ``~/Library/Caches/osc2`` on macOS;
``%LOCALAPPDATA%\\osc2\\Cache`` on Windows). ``--no-cache`` (or ``OSC2_NO_CACHE=1``,
which worker processes inherit) neither reads nor writes it.

An entry is written whole to a temporary file beside it and renamed over it
(``os.replace``), so concurrent processes read an old entry or a new one, never a
part. A reader checks the magic, the full key and a checksum, and ignores an
entry that fails any of them (rebuilding it), or that another user owns: entries
are pickles, and unpickling runs code, so only the user's own files are read.
Nothing here raises: a folder that cannot be made or written only means no cache.

Values are stored as pickles, whatever they hold: a new side table of the model
needs no code here. Dataclass instances are pickled as a call of their class
with their field values, which loads several times faster than the default
(frozen, slotted dataclasses otherwise restore field by field in Python).
"""

from __future__ import annotations

import io
import logging
import os
import pickle
import sys
import zlib
from collections.abc import Callable, Mapping
from dataclasses import fields, is_dataclass
from operator import attrgetter
from pathlib import Path
from typing import Any, TypeVar

from osc2check.fingerprint import checksum, digest, toolkit_fingerprint
from osc2check.gc_pause import gc_paused

log = logging.getLogger(__name__)

__all__ = [
    "cache_folder",
    "cached",
    "digest",
    "enabled",
    "load",
    "set_enabled",
    "store",
    "toolkit_fingerprint",
]

#: the layout of an entry file; change it when the layout or the pickling changes
FORMAT = "1"
_MAGIC = b"OSC2CACHE\n"
_KEEP = 4  # entries of one kind kept (the newest), so old versions do not pile up
_STALE_TEMP = 3600.0  # seconds after which a left-over temporary file is removed

T = TypeVar("T")

_disabled = False


def set_enabled(on: bool) -> None:
    """Turn the cache on or off for this process and the processes it starts."""
    global _disabled
    _disabled = not on
    if on:
        os.environ.pop("OSC2_NO_CACHE", None)
    else:
        os.environ["OSC2_NO_CACHE"] = "1"


def enabled() -> bool:
    return not _disabled and os.environ.get("OSC2_NO_CACHE", "") in ("", "0")


def cache_folder() -> Path:
    """Where entries are kept (not created here)."""
    chosen = os.environ.get("OSC2_CACHE_DIR")
    if chosen:
        return Path(chosen)
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or str(Path.home() / "AppData" / "Local")
        return Path(base) / "osc2" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "osc2"
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "osc2"


def _full_key(kind: str, key: Mapping[str, str], toolkit: bool = True) -> bytes:
    fields_ = {
        "kind": kind,
        "format": FORMAT,
        "toolkit": toolkit_fingerprint() if toolkit else "",
        "python": f"{sys.implementation.cache_tag} {sys.version}",
        **key,
    }
    return repr(sorted(fields_.items())).encode()


def _entry_path(kind: str, full: bytes) -> Path:
    return cache_folder() / f"{kind}-{checksum(full)[:16]}.bin"


def load(kind: str, key: Mapping[str, str], *, toolkit: bool = True) -> object | None:
    """The value stored under ``kind`` and ``key``, or None (absent, stale, corrupt,
    not the user's, or the cache is off). ``toolkit=False``: a value that does not
    depend on the toolkit's code (its key says all it depends on), kept across
    versions."""
    if not enabled():
        return None
    try:
        full = _full_key(kind, key, toolkit)
        path = _entry_path(kind, full)
        with open(path, "rb") as f:
            if hasattr(os, "getuid") and os.fstat(f.fileno()).st_uid != os.getuid():
                log.debug("cache entry %s belongs to another user: not read", path)
                return None
            data = f.read()
    except OSError:
        return None
    try:
        return _decode(data, full)
    except Exception as exc:  # any corruption: the entry is rebuilt and written again
        log.debug("cache entry %s ignored: %s", path, exc)
        return None


def store(
    kind: str, key: Mapping[str, str], value: object, *, toolkit: bool = True, keep: int = _KEEP
) -> None:
    """Write ``value`` under ``kind`` and ``key`` (atomically; failures are ignored), keeping
    the newest ``keep`` entries of ``kind``; after :func:`write_later`, when the process
    has answered."""
    if not enabled():
        return
    if _later is not None:
        _later.append((kind, dict(key), value, toolkit, keep))
        return
    _write(kind, key, value, toolkit, keep)


_later: list[tuple[str, dict[str, str], object, bool, int]] | None = None


def write_later() -> None:
    """Keep what :func:`store` is given from now on, and write it when :func:`write_kept`
    is called: for a process that answers first and fills its cache after (the resident
    checker's child, whose command has exited by then)."""
    global _later
    _later = []


def write_kept() -> None:
    """Write what :func:`store` kept since :func:`write_later`, and store at once again."""
    global _later
    kept, _later = _later or [], None
    for kind, key, value, toolkit, keep in kept:
        _write(kind, key, value, toolkit, keep)


def _write(kind: str, key: Mapping[str, str], value: object, toolkit: bool, keep: int) -> None:
    try:
        full = _full_key(kind, key, toolkit)
        data = _encode(value, full)
        path = _entry_path(kind, full)
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        import tempfile  # only writers need it (about 10 ms to import)

        fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{kind}-", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.replace(temporary, path)
        except BaseException:
            try:
                os.unlink(temporary)
            except OSError:
                pass
            raise
        _prune(path.parent, kind, path, keep)
    except Exception as exc:  # a read-only home, a full disk, a value that cannot be pickled
        log.debug("cache entry %s not written: %s", kind, exc)


def cached(
    kind: str,
    key: Mapping[str, str],
    build: Callable[[], T],
    *,
    toolkit: bool = True,
    keep: int = _KEEP,
) -> T:
    """The stored value, or ``build()`` stored for next time (``toolkit``: see ``load``;
    ``keep``: see ``store``)."""
    found = load(kind, key, toolkit=toolkit)
    if found is not None:
        return found  # type: ignore[return-value]  # stored by this function with this key
    value = build()
    store(kind, key, value, toolkit=toolkit, keep=keep)
    return value


# ---------------------------------------------------------------- entry files


def _encode(value: object, full_key: bytes) -> bytes:
    buffer = io.BytesIO()
    try:
        _Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL).dump(value)
    except RecursionError:  # a cycle through frozen dataclasses: the default way copes
        buffer = io.BytesIO()
        pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL).dump(value)
    payload = buffer.getvalue()
    header = b"%d %d %d\n" % (len(full_key), len(payload), zlib.crc32(payload))
    return _MAGIC + header + full_key + payload


def _decode(data: bytes, full_key: bytes) -> object:
    if not data.startswith(_MAGIC):
        raise ValueError("not a cache entry")
    end = data.index(b"\n", len(_MAGIC))
    key_size, size, crc = (int(x) for x in data[len(_MAGIC) : end].split())
    start = end + 1
    if data[start : start + key_size] != full_key:
        raise ValueError("another key")
    payload = memoryview(data)[start + key_size :]
    if len(payload) != size or zlib.crc32(payload) != crc:
        raise ValueError("truncated or damaged")
    with gc_paused():  # tens of thousands of objects that all live on: nothing to collect
        return pickle.loads(payload)


_FIELDS: dict[type, tuple[str, ...] | None] = {}


def _init_fields(cls: type) -> tuple[str, ...] | None:
    """The fields of a slotted dataclass ``cls`` that ``cls(*values)`` rebuilds, in
    order; None when it is not one, or restores itself in its own way."""
    try:
        return _FIELDS[cls]
    except KeyError:
        pass
    names = None
    if (
        is_dataclass(cls)
        and "__slots__" in cls.__dict__
        and not hasattr(cls, "__post_init__")
        and "__reduce__" not in cls.__dict__
        and "__reduce_ex__" not in cls.__dict__
    ):
        declared = fields(cls)
        if all(f.init for f in declared):
            names = tuple(f.name for f in declared)
    _FIELDS[cls] = names
    return names


class _Pickler(pickle.Pickler):
    """Slotted dataclasses as ``cls(*fields)``: loads without a Python call per field
    (their default ``__setstate__`` sets each field through ``object.__setattr__``)."""

    def reducer_override(self, obj: object) -> Any:
        cls = type(obj)
        try:
            values = _VALUES[cls]
        except KeyError:
            values = _VALUES[cls] = _values_getter(_init_fields(cls))
        if values is None:
            return NotImplemented
        return cls, values(obj)


#: by class, what gives the values ``cls(*values)`` rebuilds an object from (None: not
#: a slotted dataclass): a C ``attrgetter`` where it can, called once per object pickled
_VALUES: dict[type, Callable[[Any], tuple[object, ...]] | None] = {}


def _values_getter(names: tuple[str, ...] | None) -> Callable[[Any], tuple[object, ...]] | None:
    if names is None:
        return None
    if len(names) > 1:
        return attrgetter(*names)
    if names:
        one = attrgetter(names[0])
        return lambda obj: (one(obj),)
    return lambda obj: ()


def _entry_of(name: str, kind: str) -> bool:
    """Whether file ``name`` is an entry of ``kind`` (not of a kind that begins like it)."""
    digest_ = name[len(kind) + 1 : -len(".bin")]
    return (
        name.startswith(f"{kind}-")
        and name.endswith(".bin")
        and len(digest_) == 16
        and all(c in "0123456789abcdef" for c in digest_)
    )


def _prune(folder: Path, kind: str, written: Path, keep: int) -> None:
    """Remove all but the newest ``keep`` entries of ``kind``, and left-over temporary files."""
    import time

    try:
        entries = []
        now = time.time()
        for item in folder.iterdir():
            name = item.name
            if _entry_of(name, kind) and item != written:
                entries.append((item.stat().st_mtime, item))
            elif name.startswith(".") and name.endswith(".tmp"):
                if now - item.stat().st_mtime > _STALE_TEMP:
                    item.unlink()
        entries.sort(reverse=True)
        for _, item in entries[keep - 1 :]:
            item.unlink()
    except OSError:
        pass
