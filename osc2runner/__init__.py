"""osc2runner: the reference runner of the osc2 toolkit.

Scenarios are compiled to py_trees behaviour trees (``compile/``) and ticked
against a MuJoCo world of vehicles (``sim/``) at a fixed control rate::

    from osc2runner import run
    result = run("examples/cut_in_and_stop.osc", out="out", plot=True)
    result.outcome.status              # "success"
    result.telemetry["hero"]["speed"]  # numpy array, one value per tick

The command is ``osc2run`` (``python -m osc2runner``); see docs/runner.md.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from osc2runner.runner import RunResult

__all__ = ["RunResult", "run"]


def run(
    path: str | Path,
    *,
    scenario: str | None = None,
    seed: int = 0,
    out: str | Path | None = None,
    duration: float | None = None,
    dt_control: float = 0.05,
    dt_physics: float = 0.002,
    plot: bool = False,
    progress: Callable[[float, float, float], None] | None = None,
    values: Any = None,
    source: str | None = None,
) -> RunResult:
    """Run one scenario of an ``.osc`` file; see :func:`osc2runner.runner.run`."""
    from osc2runner.runner import run as _run

    return _run(path, scenario=scenario, seed=seed, out=out, duration=duration,
                dt_control=dt_control, dt_physics=dt_physics, plot=plot, progress=progress,
                values=values, source=source)


def __getattr__(name: str) -> Any:
    if name == "RunResult":
        from osc2runner.runner import RunResult

        return RunResult
    raise AttributeError(name)
