"""Other projects' public scenarios (CARLA scenario_runner, scenario_execution, py-osc2,
Scena): whatever ``osc2check`` reports, ``osc2run`` never crashes, and refuses only
with what the checker reported (an error, or A308 for a form it does not execute).

The files are read from the folder named by ``OSC2_THIRD_PARTY`` (one folder per
project: ``carla``, ``scenario_execution``, ``py-osc2``, ``scena``); without it the
tests skip. A file that declares no scenario is a library, not a runnable scenario.
Each file runs for at most two simulated seconds: enough for every start, modifier
and refusal to show.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.errors import ScenarioError

PROJECTS = ("carla", "scenario_execution", "py-osc2", "scena")
ROOT = os.environ.get("OSC2_THIRD_PARTY")


def _files(project: str) -> list[Path]:
    if ROOT is None:
        return []
    return sorted((Path(ROOT) / project).rglob("*.osc"))


def _outcome(path: Path) -> str:
    """``ran``, ``refused`` (by the checker's findings), ``library`` or what went wrong."""
    try:
        run(path, duration=2.0)
    except ScenarioError as exc:
        if exc.diagnostics and not exc.problems:
            return "refused"
        messages = [p.message for p in exc.problems]
        if messages and all("declares no scenario" in m for m in messages):
            return "library"
        return f"refused without the checker: {messages}"
    except Exception as exc:  # noqa: BLE001 - an internal error is what this test finds
        return f"internal error: {type(exc).__name__}: {exc}"
    return "ran"


@pytest.mark.skipif(ROOT is None, reason="OSC2_THIRD_PARTY names no folder")
@pytest.mark.parametrize("project", PROJECTS)
def test_third_party_scenarios_run_or_are_refused_by_the_checker(project: str) -> None:
    files = _files(project)
    if not files:
        pytest.skip(f"no {project} files under {ROOT}")
    outcomes = {str(f.relative_to(ROOT or "")): _outcome(f) for f in files}
    counts: dict[str, int] = {}
    for outcome in outcomes.values():
        key = outcome if outcome in ("ran", "refused", "library") else "wrong"
        counts[key] = counts.get(key, 0) + 1
    print(f"\n{project}: {len(files)} files, {counts}")  # the per-project figures
    wrong = {f: o for f, o in outcomes.items() if o not in ("ran", "refused", "library")}
    assert not wrong, "\n".join(f"{f}: {o}" for f, o in wrong.items())
