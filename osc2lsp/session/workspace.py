"""The workspace's sources that are not open, found and read as ``osc2check`` does."""

from __future__ import annotations

import logging
import re
from pathlib import Path

from osc2check.config import DEFAULT_EXCLUDE
from osc2check.inputs import InputError, read_bytes, walk
from osc2check.resources import stdlib_dir
from osc2check.source import decode_source

log = logging.getLogger(__name__)


def workspace_sources(
    root: Path,
    limit: int,
    open_keys: set[str],
    known: dict[str, tuple[float, str]],
    mentioning: str,
) -> list[tuple[str, float, str, bool]]:
    """``(key, mtime, text, mentions)`` of the first ``limit`` sources below ``root``
    that are not open (the text of ``known`` when the file has not changed since), as
    ``osc2check`` walks and reads them; the folders it skips by default, hidden ones and
    the bundled library are left out. ``mentions``: the text has ``mentioning`` as a
    whole word. On a thread: it reads files."""
    library = stdlib_dir().resolve()

    def excluded(path: Path) -> bool:
        name = path.name
        if name.endswith(".osc"):
            return False
        return name in DEFAULT_EXCLUDE or name.startswith(".") or path.resolve() == library

    if not root.is_dir():
        return []
    word = re.compile(rf"(?<!\w){re.escape(mentioning)}(?!\w)")
    found = []
    for met in walk(root, excluded):
        if met.why is not None:
            log.debug("workspace search: %s left out: %s", met.path, met.why)
            continue
        key = str(met.path)
        if key in open_keys:
            continue
        try:
            mtime = met.path.stat().st_mtime
            cached = known.get(key)
            if cached is not None and cached[0] == mtime:
                text = cached[1]
            else:
                text, _ = decode_source(read_bytes(met.path))
        except (OSError, InputError) as exc:
            log.debug("workspace search: %s left out: %s", met.path, exc)
            continue
        found.append((key, mtime, text, bool(word.search(text))))
        if len(found) >= limit:
            break
    return found
