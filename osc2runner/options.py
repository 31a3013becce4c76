"""The options of a run, checked before anything runs (the command's and ``run()``'s).

Each check returns the value to use or raises :class:`OptionError`, which the
command prints as one line ``osc2run: error: --name VALUE: why`` (exit
status 2) and the Python API raises as it is (a ``ValueError``):

* ``seed``: a non-negative integer (the checker's rule: ``-1`` would draw the
  same witness as ``1``);
* ``duration``: a positive, finite number of simulated seconds;
* ``dt_control``, ``dt_physics``: positive and finite, ``dt_control`` a whole
  multiple of ``dt_physics`` (at most :data:`MAX_SUBSTEPS` physics steps per
  tick; the world's own condition, to a relative 1e-9);
* ``out``: a folder that exists and takes new files, or one that can be
  created under a writable folder (it is created when the files are written,
  so a run that never starts leaves nothing behind):
  :func:`osc2runner.output.files.output_folder`.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from osc2runner.output.files import FolderError, output_folder

__all__ = [
    "MAX_SUBSTEPS",
    "OptionError",
    "check_duration",
    "check_out",
    "check_seed",
    "check_steps",
    "check_time",
]

#: most physics steps per control tick (a smaller physics step is a mistyped option)
MAX_SUBSTEPS = 100_000


class OptionError(ValueError):
    """A bad option: ``name`` (as in ``run()``: ``dt_physics``), the ``value`` given, ``why``."""

    def __init__(self, name: str, value: object, why: str) -> None:
        self.name = name
        self.value = value
        self.why = why
        super().__init__(f"{name}={value!r}: {why}")

    @property
    def cli(self) -> str:
        """The message as the command says it: ``--dt-physics 0: must be positive``."""
        return f"--{self.name.replace('_', '-')} {self.value}: {self.why}"


def check_seed(value: object) -> int:
    """``value`` as a seed: a non-negative integer (not a bool, not a float)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise OptionError("seed", value, "must be a non-negative integer")
    if value < 0:
        raise OptionError(
            "seed", value, "must be a non-negative integer (-N draws the same witness as N)"
        )
    return value


def check_time(name: str, value: object) -> float:
    """``value`` as a positive, finite time in seconds."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OptionError(name, value, "must be a number of seconds")
    seconds = float(value)
    if not math.isfinite(seconds):
        raise OptionError(name, value, "must be a finite number of seconds")
    if seconds <= 0.0:
        raise OptionError(name, value, "must be positive")
    return seconds


def check_duration(value: object) -> float | None:
    """The time limit: None (the default) or a positive, finite number of seconds."""
    return None if value is None else check_time("duration", value)


def check_steps(dt_control: object, dt_physics: object) -> tuple[float, float]:
    """The control period and the physics step: both positive and finite, the first a
    whole multiple (1 to :data:`MAX_SUBSTEPS`) of the second."""
    control = check_time("dt_control", dt_control)
    physics = check_time("dt_physics", dt_physics)
    ratio = control / physics
    substeps = round(ratio) if math.isfinite(ratio) else 0
    if substeps < 1 or abs(substeps * physics - control) > 1e-9 * control:
        raise OptionError(
            "dt_control",
            dt_control,
            f"must be a whole multiple of the physics step {dt_physics} s "
            f"(it is {ratio:.6g} times it)",
        )
    if substeps > MAX_SUBSTEPS:
        raise OptionError(
            "dt_physics",
            dt_physics,
            f"is too small: {substeps} physics steps per control tick (at most {MAX_SUBSTEPS})",
        )
    return control, physics


def check_out(value: str | os.PathLike[str], *, create: bool = False) -> Path:
    """The output folder, checked by writing a file in it (or in the folder it would be
    created in: a missing folder is created only with ``create``, when the files are
    written)."""
    try:
        return output_folder(value, create=create)
    except FolderError as exc:
        raise OptionError("out", os.fspath(value), exc.why) from None
