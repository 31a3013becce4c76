"""The checker and the runner read every generated call the same way (issue 19, item 6).

Every cell of :func:`.cases.cells` (every action of every library actor type with each
of its modifiers, and every form of every modifier on the open actions: reference,
``at:``, range or scalar) gets one case drawn by hypothesis, with a fixed seed
(``derandomize``). The cases go through the checker and the runner's compiler up to
tick 0 in chunks (:mod:`.batch`); the first accepted case of every
:data:`SIMULATE_EVERY`-th chunk is also run briefly (:func:`.harness.verdict`: an
outcome, every argument read, the modifier's effect in the telemetry).
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from tests.osc2runner.differential.batch import agree
from tests.osc2runner.differential.cases import case_strategy, cells
from tests.osc2runner.differential.harness import verdict
from tests.osc2runner.differential.library import library
from tests.osc2runner.differential.properties import PROPERTIES

CHUNK = 50
SIMULATE_EVERY = 4
CELLS = cells()
CHUNKS = [CELLS[k : k + CHUNK] for k in range(0, len(CELLS), CHUNK)]

ONCE = settings(
    max_examples=1,
    derandomize=True,
    database=None,
    deadline=None,
    phases=[Phase.generate],
    suppress_health_check=list(HealthCheck),
)


def test_at_least_three_thousand_cases_per_run():
    assert len(CELLS) >= 3000


def test_generator_covers_the_library():
    """Every library action and modifier of an actor the world builds is in a cell."""
    lib = library()
    covered = {c.action for c in CELLS} | {c.modifier for c in CELLS if c.modifier}
    wanted = {a.label for actions in lib.actions.values() for a in actions}
    wanted |= {m.label for mods in lib.modifiers.values() for m in mods}
    assert wanted - covered == set()


def test_every_modifier_has_a_property():
    lib = library()
    names = {m.name for mods in lib.modifiers.values() for m in mods}
    assert names - PROPERTIES.keys() == set()


@pytest.mark.parametrize(
    "chunk",
    # the fast subset (`-m "not slow"`, docs/testing.md) keeps the first chunk; CI runs all
    [pytest.param(k, marks=() if k == 0 else pytest.mark.slow) for k in range(len(CHUNKS))],
)
def test_checker_and_runner_agree(chunk: int) -> None:
    @ONCE
    @given(st.data())
    def agree_on_chunk(data: st.DataObject) -> None:
        cases = [data.draw(case_strategy(cell), label=cell.id) for cell in CHUNKS[chunk]]
        outcome = agree(cases)
        assert len(outcome.accepted) + len(outcome.refused) == len(cases)
        if chunk % SIMULATE_EVERY == 0 and outcome.accepted:
            verdict(cases[min(outcome.accepted)])

    agree_on_chunk()
