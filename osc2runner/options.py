"""The options of a run, checked before anything runs (the command's and ``run()``'s).

:class:`RunOptions` holds them, made once by each command line and by ``run()``
(:meth:`RunOptions.checked`) and read by every stage; a campaign's options extend
it (:class:`osc2runner.campaign.campaign.CampaignOptions`), a run's replay command
is written from it. Their defaults are written here and nowhere else
(:data:`DT_CONTROL`, :data:`DT_PHYSICS`, :data:`TIME_LIMIT`).

Each check returns the value to use or raises :class:`OptionError`, which the
command prints as one line ``osc2run: error: --name VALUE: why`` (exit
status 2) and the Python API raises as it is (a ``ValueError``):

* ``seed``: a non-negative integer (the checker's rule: ``-1`` would draw the
  same witness as ``1``);
* ``duration``: a positive, finite number of simulated seconds;
* ``dt_control``, ``dt_physics``: positive and finite, ``dt_control`` a whole
  multiple of ``dt_physics`` (at most :data:`MAX_SUBSTEPS` physics steps per
  tick; the world's own condition, to a relative 1e-9);
* ``kinematic``: the vehicles moved by the kinematic model, as names or
  shell-style patterns (``npc*``, ``*``), each a non-empty text; which vehicles
  they may name is the runner's rule (:func:`osc2runner.runner.build_world`);
* ``out``: a folder that exists and takes new files, or one that can be
  created under a writable folder (it is created when the files are written,
  so a run that never starts leaves nothing behind):
  :func:`osc2runner.output.files.output_folder`.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from osc2runner.output.files import FolderError, output_folder

if TYPE_CHECKING:
    from osc2check.config import Config
    from osc2runner.sut.loading import SutSpec

__all__ = [
    "DT_CONTROL",
    "DT_PHYSICS",
    "MAX_SUBSTEPS",
    "TIME_LIMIT",
    "OptionError",
    "RunOptions",
    "check_duration",
    "check_kinematic",
    "check_out",
    "check_seed",
    "check_steps",
    "check_time",
]

#: most physics steps per control tick (a smaller physics step is a mistyped option)
MAX_SUBSTEPS = 100_000
#: the control period (one tick of the behaviour tree), s
DT_CONTROL = 0.05
#: the physics step, s
DT_PHYSICS = 0.002
#: the time limit of a run without ``duration``, s of simulated time
TIME_LIMIT = 600.0


@dataclass(frozen=True, slots=True, kw_only=True)
class RunOptions:
    """What one run is asked to do, whatever asks (the command, ``run()``, a campaign):
    two runs of one file with equal options and seed tick the same.

    ``config`` is the checker's configuration (None: the one that applies to the file);
    ``sut`` the system under test, loaded; ``plot`` also writes PNG plots.
    Made with :meth:`checked` where the values come from a user."""

    scenario: str | None = None
    seed: int = 0
    duration: float | None = None  # None: TIME_LIMIT
    dt_control: float = DT_CONTROL
    dt_physics: float = DT_PHYSICS
    sut: SutSpec | None = None
    config: Config | None = None
    plot: bool = False
    kinematic: tuple[str, ...] = ()  # vehicles (names, patterns) on the kinematic model

    @classmethod
    def checked(
        cls,
        *,
        scenario: str | None = None,
        seed: object = 0,
        duration: object = None,
        dt_control: object = DT_CONTROL,
        dt_physics: object = DT_PHYSICS,
        sut: SutSpec | None = None,
        config: Config | None = None,
        plot: bool = False,
        kinematic: object = (),
    ) -> RunOptions:
        """The options with each value checked (:class:`OptionError`, in the order the
        checks have always run: seed, steps, duration)."""
        good_seed = check_seed(seed)
        control, physics = check_steps(dt_control, dt_physics)
        return cls(
            scenario=scenario,
            seed=good_seed,
            duration=check_duration(duration),
            dt_control=control,
            dt_physics=physics,
            sut=sut,
            config=config,
            plot=plot,
            kinematic=check_kinematic(kinematic),
        )

    @property
    def time_limit(self) -> float:
        """The simulated seconds the run may take: ``duration``, else :data:`TIME_LIMIT`."""
        return TIME_LIMIT if self.duration is None else self.duration

    def run_fields(self) -> dict[str, Any]:
        """The run's options alone, by name (what a class that extends these passes on)."""
        return {f.name: getattr(self, f.name) for f in fields(RunOptions)}

    def for_seed(self, seed: int) -> RunOptions:
        """The run's options alone, for ``seed`` (one run of a campaign)."""
        return RunOptions(**{**self.run_fields(), "seed": seed})


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


def check_kinematic(value: object) -> tuple[str, ...]:
    """The vehicles on the kinematic model: names or shell-style patterns, each a
    non-empty text without a comma (the command separates them by commas)."""
    items = (value,) if isinstance(value, str) else value
    if not isinstance(items, (list, tuple)):
        raise OptionError("kinematic", value, "must be actor names or patterns")
    for item in items:
        if not isinstance(item, str) or not item.strip() or "," in item:
            raise OptionError("kinematic", value, f"{item!r} is not an actor name or pattern")
    return tuple(item.strip() for item in items)


def check_out(value: str | os.PathLike[str], *, create: bool = False) -> Path:
    """The output folder, checked by writing a file in it (or in the folder it would be
    created in: a missing folder is created only with ``create``, when the files are
    written)."""
    try:
        return output_folder(value, create=create)
    except FolderError as exc:
        raise OptionError("out", os.fspath(value), exc.why) from None
