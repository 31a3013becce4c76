"""Exports of a concrete run that other simulators replay (docs/export.md).

* :mod:`.recording`: what an export reads of a finished run (:func:`run_recording`);
* :mod:`.xosc`: ASAM OpenSCENARIO XML 1.2, with the road network beside it;
* :mod:`.xodr`: a built-in road written as ASAM OpenDRIVE;
* :mod:`.osi`: ASAM OSI ground truth, one message a control tick.

The writers need the ``export`` extra (``pip install "osc2-toolkit[export]"``:
scenariogeneration, the OSI bindings and asam-osi-utilities);
:func:`missing_extra` says so before anything runs. An export is written after
the run, before ``run.json`` (:func:`osc2runner.runner.execute`, ``export=``).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from osc2runner.runner import Prepared, RunResult

__all__ = [
    "FILE_NAMES",
    "FORMATS",
    "INSTALL_EXTRA",
    "ExportTargets",
    "export_run",
    "missing_extra",
]

#: the export formats, and the file each is written to in a run's folder (``--export``)
FILE_NAMES = {"xosc": "scenario.xosc", "osi": "ground_truth.osi"}
FORMATS = tuple(FILE_NAMES)
INSTALL_EXTRA = 'pip install "osc2-toolkit[export]"'
#: the modules each format's writer imports
_MODULES = {"xosc": ("scenariogeneration",), "osi": ("osi3", "osi_utilities")}


@dataclass(frozen=True)
class ExportTargets:
    """Where a run's exports go: an OpenSCENARIO file (its road network is written
    beside it) and an OSI trace; None: not written."""

    xosc: Path | None = None
    osi: Path | None = None

    @classmethod
    def in_folder(cls, folder: Path, formats: Iterable[str]) -> ExportTargets:
        """The exports ``formats`` under their :data:`FILE_NAMES` in ``folder``."""
        chosen = set(formats)
        return cls(
            folder / FILE_NAMES["xosc"] if "xosc" in chosen else None,
            folder / FILE_NAMES["osi"] if "osi" in chosen else None,
        )

    def __bool__(self) -> bool:
        return self.xosc is not None or self.osi is not None


def missing_extra(formats: Iterable[str]) -> str | None:
    """A one-line message naming the extra to install when a writer of ``formats``
    cannot be imported; None when all can."""
    missing = sorted(
        {m for f in formats for m in _MODULES[f] if importlib.util.find_spec(m) is None}
    )
    if not missing:
        return None
    return f"exporting needs the export extra ({', '.join(missing)} missing): {INSTALL_EXTRA}"


def export_run(prepared: Prepared, result: RunResult, targets: ExportTargets) -> list[Path]:
    """Write a finished run's exports (their folders made when missing); returns the
    files written."""
    from osc2runner.export.recording import run_recording
    from osc2runner.output.files import output_folder

    for target in (targets.xosc, targets.osi):
        if target is not None:
            output_folder(target.parent)  # checked before the run; made now
    recording = run_recording(prepared, result)
    written: list[Path] = []
    if targets.xosc is not None:
        from osc2runner.export.xosc import write_xosc

        written += write_xosc(recording, targets.xosc)
    if targets.osi is not None:
        from osc2runner.export.osi import write_osi

        written.append(write_osi(recording, targets.osi))
    return written
