"""Composites with scripted children, tick by tick.

Each table has one row per tick: the status of the composite, then of each
child (R running, S success, F failure, - invalid), after that tick.
"""

from __future__ import annotations

import numpy as np
import py_trees
import pytest
from py_trees.behaviours import StatusQueue
from py_trees.common import Status

from osc2runner.compile.composites import (
    DurationBound,
    Labelled,
    OneOf,
    Parallel,
    ScenarioRoot,
    Serial,
    running_open,
)
from osc2runner.compile.conditions import LevelWatch, Until

R, S, F = Status.RUNNING, Status.SUCCESS, Status.FAILURE
LETTER = {Status.RUNNING: "R", Status.SUCCESS: "S", Status.FAILURE: "F", Status.INVALID: "-"}


def script(name: str, *statuses: Status, then: Status | None = None) -> StatusQueue:
    return StatusQueue(name, queue=list(statuses), eventually=then)


class FakeContext:
    """Just what composites read: tick, dt, and emit (recorded)."""

    def __init__(self, seed: int = 0) -> None:
        self.tick = 0
        self.dt = 0.5
        self.emitted: list[tuple[int, str]] = []
        self.failed: str | None = None
        self.records: list[tuple[str, str, str]] = []
        self.rng = np.random.default_rng(seed)

    def record(self, kind: str, name: str, detail: str = "") -> None:
        self.records.append((kind, name, detail))

    def fail(self, reason: str) -> None:
        self.failed = self.failed or reason

    def emit(self, name: str, args: object = None, *, kind: str = "emit") -> None:
        self.emitted.append((self.tick, name))


def table(
    root: py_trees.behaviour.Behaviour, nodes: list, ticks: int, ctx: FakeContext | None = None
) -> list[str]:
    if ctx is not None:
        py_trees.trees.setup(root, context=ctx)
    rows = []
    for k in range(ticks):
        if ctx is not None:
            ctx.tick = k
        root.tick_once()
        rows.append(" ".join(LETTER[n.status] for n in [root, *nodes]))
    return rows


def test_serial_hands_over_in_the_same_tick():
    a = script("a", R, S)
    b = script("b", S)
    c = script("c", R, R, S)
    root = Serial("serial", [a, b, c])
    # Expect: a runs, then a and b finish and c starts in the same tick, then c ends
    assert table(root, [a, b, c], 4) == [
        "R R - -",
        "R S S R",
        "R S S R",
        "S S S S",
    ]


def test_serial_fails_with_its_member():
    a = script("a", S)
    b = script("b", R, F)
    c = script("c", S)
    root = Serial("serial", [a, b, c])
    assert table(root, [a, b, c], 2) == [
        "R S R -",
        "F S F -",
    ]


def test_parallel_joins_on_all_and_does_not_retick_finished_members():
    a = script("a", S, then=F)  # would fail if ticked again
    b = script("b", R, R, S)
    root = Parallel("parallel", [a, b])
    assert table(root, [a, b], 3) == [
        "R S R",
        "R S R",
        "S S S",
    ]


def test_parallel_first_failure_stops_the_others():
    a = script("a", R, F)
    b = script("b", R, R, R)
    root = Parallel("parallel", [a, b])
    assert table(root, [a, b], 2) == [
        "R R R",
        "F F -",
    ]


def test_parallel_ends_open_ended_members_with_the_others():
    a = script("a", R, S)
    drive = script("drive", then=R)
    drive.open_ended = True  # as the compiler marks drive() without duration/until
    root = Parallel("parallel", [a, drive])
    # Expect: once `a` is done only the open-ended drive runs: the parallel succeeds
    assert table(root, [a, drive], 2) == [
        "R R R",
        "S S -",
    ]


def test_parallel_of_open_ended_members_keeps_running():
    x, y = script("x", then=R), script("y", then=R)
    x.open_ended = y.open_ended = True
    root = Parallel("parallel", [x, y])
    assert table(root, [x, y], 3) == ["R R R"] * 3
    assert running_open(root)


def test_one_of_a_waiting_member_ends_the_acting_one():
    """The paper's idiom: `one_of: drive() / wait fall(...)`; the wait ends it."""
    drive = script("drive", then=R)
    wait = script("wait", R, R, S)
    root = OneOf("one_of", [drive, wait], acting=[True, False])
    assert table(root, [drive, wait], 3, FakeContext()) == [
        "R R R",
        "R R R",
        "S - S",  # the acting member is stopped
    ]
    assert root.winner is wait


@pytest.mark.parametrize("seed", range(6))
def test_one_of_runs_exactly_one_acting_member_chosen_by_the_seed(seed):
    a, b = script("a", R, S), script("b", R, S)
    ctx = FakeContext(seed)
    root = OneOf("one_of", [a, b], acting=[True, True])
    rows = table(root, [a, b], 2, ctx)
    chosen = root.chosen
    assert chosen in (a, b)
    other = b if chosen is a else a
    column = 1 if chosen is a else 2
    assert [row.split()[column] for row in rows] == ["R", "S"]
    assert {row.split()[3 - column] for row in rows} == {"-"}  # never started
    assert ctx.records == [("choice", "one_of", f"member {column} of 2: {chosen.name}")]
    assert other.status == Status.INVALID


def test_one_of_choices_spread_over_seeds():
    chosen = set()
    for seed in range(20):
        a, b = script("a", R), script("b", R)
        root = OneOf("one_of", [a, b], acting=[True, True])
        table(root, [a, b], 1, FakeContext(seed))
        chosen.add(root.chosen.name)
    assert chosen == {"a", "b"}


def test_one_of_fails_when_its_chosen_member_fails():
    a = script("a", R, F)
    wait = script("wait", then=R)
    root = OneOf("one_of", [a, wait], acting=[True, False])
    assert table(root, [a, wait], 2, FakeContext()) == ["R R R", "F F -"]


def test_one_of_with_only_waiting_members_is_a_race():
    a, b = script("a", R, S), script("b", R, R, S)
    root = OneOf("one_of", [a, b], acting=[False, False])
    assert table(root, [a, b], 2, FakeContext()) == ["R R R", "S S -"]


def test_duration_ends_an_open_ended_child_at_the_upper_bound():
    ctx = FakeContext()  # dt 0.5 s
    child = script("drive", then=R)
    child.endless = True  # an action that cannot end on its own, as drive()
    root = DurationBound("duration: 1.5s", child, lambda: (1.5, 1.5))
    # Expect: the child runs for ticks 0..2 (1.5 s); at tick 3 the phase ends
    assert table(root, [child], 5, ctx) == [
        "R R",
        "R R",
        "R R",
        "S -",
        "R R",  # a new phase when ticked again
    ]


def test_a_goal_not_reached_within_the_duration_fails_the_phase():
    ctx = FakeContext()
    child = script("change_speed", then=R)  # has a goal: not endless
    root = DurationBound("change_speed, duration: 1s", child, lambda: (1.0, 1.0), "f.osc:3:5")
    # Expect: running for 1 s, then the phase fails, naming where
    assert table(root, [child], 3, ctx) == ["R R", "R R", "F -"]
    assert ctx.failed == ("f.osc:3:5: `change_speed` did not complete within its duration (1 s)")


def test_a_goal_reached_in_the_tick_the_duration_ends_ends_on_time():
    # §7.6.2: a phase of duration d may end at d; a change planned over the whole phase
    # (or `wait elapsed(d)`) completes in the tick its bound is reached
    ctx = FakeContext()
    child = script("change_speed", R, R, S, then=F)
    root = DurationBound("change_speed, duration: 1s", child, lambda: (1.0, 1.0), "f.osc:3:5")
    assert table(root, [child], 3, ctx) == ["R R", "R R", "S S"]
    assert ctx.failed is None


def test_duration_holds_an_early_success_until_the_lower_bound():
    ctx = FakeContext()
    child = script("change", R, S, then=F)  # must not be ticked again once done
    root = DurationBound("duration: [1s..3s]", child, lambda: (1.0, 3.0))
    assert table(root, [child], 3, ctx) == [
        "R R",
        "R S",  # done at 0.5 s: held, not ticked again
        "S S",  # 1.0 s: the lower bound is reached
    ]


def test_until_ends_the_phase_when_its_event_occurs():
    ctx = FakeContext()
    flag = {"on": False}
    child = script("drive", then=R)
    root = Until("until", child, LevelWatch(lambda: flag["on"]))
    rows = []
    for k in range(3):
        flag["on"] = k == 2
        root.tick_once()
        rows.append(f"{LETTER[root.status]} {LETTER[child.status]}")
    # Expect: checked before the child is ticked, so the phase ends at the event's tick
    assert rows == ["R R", "R R", "S -"]
    assert ctx.tick == 0


def test_labelled_member_emits_start_and_end():
    ctx = FakeContext()
    child = script("x", R, S)
    root = Labelled("lbl:", child, "lbl")
    assert table(root, [child], 2, ctx) == ["R R", "S S"]
    assert ctx.emitted == [(0, "lbl.start"), (1, "lbl.end")]


def test_scenario_root_follows_its_do_and_stops_handlers():
    ctx = FakeContext()
    do = script("do", R, S)
    handler = script("on", then=R)
    root = ScenarioRoot("scenario", do, [handler])
    assert table(root, [do, handler], 2, ctx) == ["R R R", "S S -"]
    assert ctx.emitted == [(0, "start"), (1, "end")]


@pytest.mark.parametrize("composite", [Serial, Parallel, OneOf])
def test_empty_composites_succeed(composite):
    root = composite("empty", [])
    root.tick_once()
    assert root.status == S


def test_composites_render_with_py_trees_glyphs():
    tree = Serial(
        "serial [1]",
        [Parallel("parallel [2]", [script("a", S)]), OneOf("one_of [3]", [script("b", S)])],
    )
    text = py_trees.display.unicode_tree(tree)
    assert text.splitlines() == [
        "{-} serial [1]",
        "    /_/ parallel [2]",
        "        --> a",
        "    /_/ one_of [3]",
        "        --> b",
    ]


@pytest.mark.parametrize("overlap", ["start", "any", "full"])
def test_parallel_joins_on_every_member(overlap):
    a, b = script("a", R, S), script("b", R, R, R, S)
    root = Parallel("parallel", [a, b], overlap)
    # Expect: done when the last member is done; a, done early, is not ticked again
    assert table(root, [a, b], 4, FakeContext()) == ["R R R", "R S R", "R S R", "S S S"]


@pytest.mark.parametrize("overlap", ["equal", "end", "final", "initial", "inside"])
def test_parallel_ends_with_its_first_member_and_stops_open_ended_others(overlap):
    first, other = script("first", R, S), script("drive", then=R)
    other.endless = True
    root = Parallel("parallel", [first, other], overlap)
    assert table(root, [first, other], 2, FakeContext()) == ["R R R", "S S -"]


@pytest.mark.parametrize("overlap", ["equal", "end", "final", "initial", "inside"])
def test_parallel_fails_when_a_member_with_a_goal_is_stopped_by_the_first(overlap):
    first, other = script("first", R, S), script("change_speed", then=R)
    ctx = FakeContext()
    root = Parallel("parallel", [first, other], overlap, "f.osc:4:9")
    assert table(root, [first, other], 2, ctx) == ["R R R", "F S -"]
    assert ctx.failed == (
        f"f.osc:4:9: `change_speed` had not completed when the first member of "
        f"`parallel(overlap: {overlap})` ended"
    )


def test_parallel_equal_holds_a_member_done_early_until_the_first_ends():
    first, other = script("first", R, R, S), script("other", S)
    root = Parallel("parallel", [first, other], "equal")
    assert table(root, [first, other], 3, FakeContext()) == ["R R S", "R R S", "S S S"]
