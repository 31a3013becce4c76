"""What identifies the toolkit's code and a text, cheaply: for the start-up cache's keys
(:mod:`osc2check.cache`) and the resident checker's address (:mod:`osc2check.resident`).

Imported by the ``osc2check`` command before anything else, so it imports nothing
more than the interpreter has loaded at start.
"""

from __future__ import annotations

import os
import threading
import zlib

__all__ = ["digest", "checksum", "toolkit_fingerprint"]

_PACKAGE = os.path.dirname(os.path.realpath(__file__))
_lock = threading.Lock()
_toolkit: str | None = None


def toolkit_fingerprint() -> str:
    """A digest of every file of ``osc2check``, the grammar and the standard library
    (inside the package when installed, beside it in a checkout:
    :mod:`osc2check.resources`): its path, size and modification time."""
    global _toolkit
    with _lock:
        if _toolkit is None:
            parts: list[str] = []
            roots = [_PACKAGE]
            for name in ("grammar", "stdlib"):  # where resources.data_dir finds them
                if not os.path.isdir(os.path.join(_PACKAGE, name)):
                    beside = os.path.join(os.path.dirname(_PACKAGE), name)
                    if os.path.isdir(beside):
                        roots.append(beside)
            for root in roots:
                for folder, subfolders, files in os.walk(root):
                    subfolders[:] = sorted(d for d in subfolders if d != "__pycache__")
                    for name in sorted(files):
                        if not name.endswith((".pyc", ".pyo")):
                            try:
                                st = os.stat(os.path.join(folder, name))
                            except OSError:  # a dangling link (an editor's lock file)
                                continue
                            parts.append(f"{folder}/{name}:{st.st_size}:{st.st_mtime_ns}")
            _toolkit = checksum("\n".join(parts).encode())
        return _toolkit


def digest(*texts: str) -> str:
    """A short digest of some texts, for a key field (``cached(..., {"library": ...})``)."""
    return checksum("\0".join(texts).encode("utf-8", "surrogatepass"))


def checksum(data: bytes) -> str:
    """Two checksums and the length: they tell versions of a text apart, which is all a
    key needs (an entry holds its whole key, compared on reading). No cryptographic
    hash: an attacker who can write the cache folder needs none, and importing
    ``hashlib`` costs more than the rest of a key."""
    return f"{zlib.crc32(data):08x}{zlib.adler32(data):08x}{len(data):x}"
