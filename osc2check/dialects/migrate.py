"""``osc2check migrate``: a file of another tool's dialect written as standard OSC2.

The text is the one the checker, the runner and the language server read for the
file in its dialect (:mod:`osc2check.dialects`), so the migrated file checks and
runs as the original does in that dialect, without its D findings.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.diagnostics import Diagnostic
from osc2check.dialects.carla import carla_reading, is_carla
from osc2check.dialects.rewrite import apply_edits
from osc2check.syntax import parse

__all__ = ["Migration", "migrate"]


@dataclass(frozen=True)
class Migration:
    """A file migrated: its standard text, and the forms that were rewritten (their
    findings, at the positions of the file as it was)."""

    text: str
    forms: tuple[Diagnostic, ...]
    dialect: str  # the dialect it was read in: "carla", or "standard" (nothing to do)

    @property
    def changed(self) -> bool:
        return bool(self.forms)


def migrate(text: str, uri: str, dialect: str = "auto") -> Migration:
    """``text`` (of file ``uri``) in standard OSC2: CARLA's forms rewritten when the file
    is CARLA's (``dialect`` ``auto``) or said to be (``carla``)."""
    result = parse(text, uri)
    if dialect == "standard" or (dialect == "auto" and not is_carla(result)):
        return Migration(text, (), "standard")
    reading = carla_reading(result)
    new, _ = apply_edits(text, reading.edits)
    return Migration(new, reading.findings, "carla")
