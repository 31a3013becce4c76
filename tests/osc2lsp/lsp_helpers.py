"""Shared test helpers: the `$0` cursor marker, snapshots, the conformance seed."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2lsp.state import snapshot_of

REPO = Path(__file__).resolve().parents[2]
SHARED_SEED = REPO.parent / "shared" / "conformance" / "seed" / "cut_in_and_stop.osc"
EXAMPLE_SEED = REPO / "examples" / "cut_in_and_stop.osc"
CURSOR = "$0"
URI = "file:///tmp/osc2lsp-tests/document.osc"


def seed_path(required: bool = True) -> Path:
    """The design paper's scenario from the shared conformance folder (skip when absent)."""
    if SHARED_SEED.is_file():
        return SHARED_SEED
    if required:
        pytest.skip(f"{SHARED_SEED} is not available")
    return EXAMPLE_SEED


def seed_text() -> str:
    return seed_path().read_text(encoding="utf-8")


def cursor(text: str) -> tuple[str, int]:
    """The text without its `$0` marker, and the marker's offset."""
    offset = text.index(CURSOR)
    return text.replace(CURSOR, "", 1), offset


def snapshot(text: str, uri: str = URI, config=None):
    return snapshot_of(text, uri, 1, config)


def line_of(text: str, offset: int) -> int:
    """1-based line of an offset."""
    return text.count("\n", 0, offset) + 1


def insert_line(text: str, after: str, line: str) -> str:
    """``text`` with ``line`` inserted after the first line containing ``after``."""
    lines = text.split("\n")
    index = next(i for i, current in enumerate(lines) if after in current)
    lines.insert(index + 1, line)
    return "\n".join(lines)
