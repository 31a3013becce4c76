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

from typing import Any

__all__ = ["RunResult", "run"]


def __getattr__(name: str) -> Any:
    # Imported on first use: `import osc2runner` stays cheap (no mujoco, no py_trees).
    if name in ("run", "RunResult"):
        from osc2runner import runner

        return getattr(runner, name)
    raise AttributeError(name)
