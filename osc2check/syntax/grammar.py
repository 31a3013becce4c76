"""Load the OSC2 grammar once per process and build the LALR parser from it."""

from __future__ import annotations

import hashlib
import os
import tempfile
from functools import cache
from pathlib import Path

from lark import Lark

from osc2check.resources import grammar_path


def _cache_file(text: str) -> str | None:
    """A per-user cache file for lark's analysed grammar, keyed by the grammar text."""
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    folder = Path(base) / "osc2check"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        folder = Path(tempfile.gettempdir())
    return str(folder / f"osc2-grammar-{digest}.lark-cache")


@cache
def grammar_text() -> str:
    return grammar_path().read_text(encoding="utf-8")


@cache
def lark_parser(transformer: object | None = None) -> Lark:
    """The LALR parser. Tokens are produced by our own lexer, so lark's is unused."""
    text = grammar_text()
    kwargs: dict[str, object] = dict(parser="lalr", lexer="basic", maybe_placeholders=True)
    if transformer is not None:
        kwargs["transformer"] = transformer
    try:
        return Lark(text, cache=_cache_file(text), **kwargs)
    except OSError:
        return Lark(text, **kwargs)
