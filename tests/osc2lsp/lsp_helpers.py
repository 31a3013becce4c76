"""Shared test helpers: the `$0` cursor marker, snapshots, the conformance seed."""

from __future__ import annotations

from pathlib import Path

from osc2lsp.session.analysis import snapshot_of

REPO = Path(__file__).resolve().parents[2]
SEED = REPO / "tests" / "data" / "seed" / "cut_in_and_stop.osc"  # vendored
CURSOR = "$0"
URI = "file:///tmp/osc2lsp-tests/document.osc"
# Two `keep`s no speed satisfies: only the solver's phase finds it (C401).
CONFLICT = """import osc.standard

scenario cruise_band:
    hero: vehicle
    cruise: speed
    keep(cruise in [30kph..50kph])
    keep(cruise > 60kph)
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
        speed(cruise)
"""


def seed_path() -> Path:
    """The design paper's cut-in scenario (vendored under tests/data/seed)."""
    return SEED


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
