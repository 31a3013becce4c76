"""Other tools' OSC2 dialects, read as standard OSC2.

:func:`dialect_reading` is where a file meets its dialect: the file as parsed,
or, in CARLA scenario_runner's dialect (:mod:`osc2check.dialects.carla`), the
standard OSC2 its CARLA forms mean, at the positions of the file as written.
"""

from __future__ import annotations

from osc2check.syntax import ParseResult

__all__ = ["dialect_reading", "may_read_as_carla", "reads_as_carla"]


def may_read_as_carla(text: str, dialect: str) -> bool:
    """Whether a file's text may be read in CARLA's dialect, told from the text alone:
    True for every file :func:`reads_as_carla` reads so (and for some others). The
    reading is the whole file's (its import or modifiers decide it for every line)."""
    if dialect == "standard":
        return False
    if dialect == "carla":
        return True
    from osc2check.dialects.carla import LIBRARY_FILE, WORLD_MODIFIERS

    return LIBRARY_FILE in text or any(m.split(".")[-1] in text for m in WORLD_MODIFIERS)


def reads_as_carla(result: ParseResult, dialect: str) -> bool:
    """Whether a file is read in CARLA's dialect: ``carla``, or ``auto`` and a CARLA file."""
    from osc2check.dialects.carla import is_carla

    return dialect == "carla" or (dialect == "auto" and is_carla(result))


def dialect_reading(result: ParseResult, dialect: str) -> ParseResult:
    """``result`` as its dialect reads it (``dialect`` is ``auto``, ``standard`` or
    ``carla``, :mod:`osc2check.semantics.profile`)."""
    if dialect == "standard" or not reads_as_carla(result, dialect):
        return result
    from osc2check.dialects.carla import carla_reading
    from osc2check.dialects.rewrite import read_through

    reading = carla_reading(result)
    return read_through(result, reading.edits, reading.findings)
