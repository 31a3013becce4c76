"""Locate the data files shipped with the toolkit: the grammar and the library.

In a wheel they live inside the ``osc2check`` package (``osc2check/grammar``,
``osc2check/stdlib``); in a source checkout they are the top-level
``grammar/`` and ``stdlib/`` folders.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


@cache
def data_dir(name: str) -> Path:
    """The folder ``grammar`` or ``stdlib``, wherever this installation keeps it."""
    for candidate in (_PACKAGE_DIR / name, _PACKAGE_DIR.parent / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"the toolkit's `{name}` folder is missing from this installation")


def grammar_path() -> Path:
    return data_dir("grammar") / "osc2.lark"


def stdlib_dir() -> Path:
    return data_dir("stdlib")
