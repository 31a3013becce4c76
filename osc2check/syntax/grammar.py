"""The OSC2 grammar's text, and what the parser's behaviour depends on (for caches)."""

from __future__ import annotations

import importlib.util
import os
from functools import cache

from osc2check.cache import digest
from osc2check.resources import grammar_path


@cache
def grammar_text() -> str:
    return grammar_path().read_text(encoding="utf-8")


@cache
def grammar_key() -> dict[str, str]:
    """What the parser's behaviour depends on besides the toolkit's code: the grammar's
    text and the installed lark (the size and time of its ``__init__``, not its import)."""
    spec = importlib.util.find_spec("lark")
    origin = spec.origin if spec is not None else None
    lark = ""
    if origin:
        st = os.stat(origin)
        lark = f"{origin}:{st.st_size}:{st.st_mtime_ns}"
    return {"grammar": digest(grammar_text()), "lark": lark}
