# ruff: noqa: E501
"""The timing model (B608): rule by rule, its conflicts, its witnesses, and the runner.

* Rules: one small scenario per rule of ``docs/runner.md`` ("Language semantics as
  run"), each with the verdict its text gives, and its near miss.
* Conflicts name the lines of the durations that clash, and are minimal: without any
  one of their constraints the rest can hold.
* A duration given by a parameter: the witness gives it a value that keeps the timing.
* The runner: for generated timing structures (serial, parallel with every overlap kind,
  one_of with waiting members, duration values and ranges, `until elapsed`, `wait
  elapsed`, endless and open-ended drives), the checker reports B608 exactly when the
  runner fails the scenario for timing reasons. Durations are short, so that the runs
  are quick; the checker's own timing is left out of the run's witness there, so that
  the runner runs what the checker refuses.
* The tables the model shares with the runner (instant and endless actions) agree with
  the runner's registry.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
import z3
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from osc2check.analysis import SourceInput, analyze
from osc2check.semantics.phases import ENDLESS_ACTIONS, ENDS_WITH_FIRST, INSTANT_ACTIONS
from osc2check.verify import timing
from osc2check.verify.api import solve
from osc2check.verify.witness import Witness
from osc2check.verify.z3_backend import DEFINITION, Encoder, SolverOutcome, active_constraints

URI = "timing.osc"
TIMING_FAILURES = (
    "did not complete within its duration",
    "had not completed when the first member",
    "ended before the first member",
)


def scenario(body: str, params: str = "") -> str:
    """A scenario `top` with an actor `hero` and ``body`` as its `do` (indented by 4)."""
    lines = ["import osc.standard", "", "scenario top:", "    hero: vehicle"]
    lines += [f"    {line}" for line in params.splitlines() if line.strip()]
    lines += ["    do " + body.splitlines()[0]]
    lines += [f"    {line}" for line in body.splitlines()[1:]]
    return "\n".join(lines) + "\n"


def check(text: str):
    analysis = analyze([SourceInput(URI, text)])
    errors = [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    return analysis, errors


def b608(text: str) -> list:
    _, errors = check(text)
    others = [d for d in errors if str(d.code) != "B608"]
    assert not others, [d.message for d in others]
    return [d for d in errors if str(d.code) == "B608"]


# ---- the rules, one by one ---------------------------------------------------------------

RULES = [
    # serial: members one after the other
    ("serial of waits longer than its duration", "serial(duration: 3s):\n    wait elapsed(1s)\n    wait elapsed(2.5s)", True),
    ("serial of waits exactly its duration", "serial(duration: 3s):\n    wait elapsed(1s)\n    wait elapsed(2s)", False),
    ("goals with durations longer than the serial", "serial(duration: 5s):\n    hero.change_speed(target: 20kph, duration: [4s..6s])\n    hero.change_speed(target: 10kph, duration: [3s..4s])", True),
    ("goals with durations that fit the serial", "serial(duration: [7s..8s]):\n    hero.change_speed(target: 20kph, duration: [4s..6s])\n    hero.change_speed(target: 10kph, duration: [3s..4s])", False),
    ("a goal without duration may take any time", "serial(duration: 1s):\n    hero.change_speed(target: 20kph)\n    hero.change_lane(num_of_lanes: 1, side: left)", False),
    ("an instant action takes no time", "serial(duration: 2s):\n    hero.assign_speed(speed: 10kph)\n    wait elapsed(2s)", False),
    # a duration range holds an early end until its lower bound
    ("a held member pushes the next one out", "serial(duration: 4s):\n    wait elapsed(1s) \n    serial(duration: [3s..5s]):\n        wait elapsed(1s)\n    wait elapsed(0.5s)", True),
    # the serial stops an endless member as planned: what comes after it does not run
    ("an endless member stopped by the serial's bound", "serial(duration: 3s):\n    hero.drive(duration: [1s..4s])\n    wait elapsed(2.5s)", False),
    ("a bounded endless member not yet at its lower bound", "serial(duration: 3s):\n    wait elapsed(1s)\n    hero.drive(duration: [3s..4s])", True),
    # parallel that joins on every member
    ("a join longer than its duration", "parallel(duration: 2s):\n    wait elapsed(1s)\n    wait elapsed(3s)", True),
    ("an open-ended member ends with the others", "serial(duration: 3s):\n    parallel:\n        hero.drive()\n        wait elapsed(1s)\n    wait elapsed(2s)", False),
    ("an open-ended member does not shorten a wait", "serial(duration: 3s):\n    parallel:\n        hero.drive()\n        wait elapsed(1s)\n    wait elapsed(2.5s)", True),
    ("overlap any joins too", "parallel(overlap: any, duration: 2s):\n    wait elapsed(1s)\n    wait elapsed(3s)", True),
    # parallel that ends with its first member
    ("overlap equal: a wait outlasts the first", "parallel(overlap: equal):\n    hero.drive(duration: 1s)\n    wait elapsed(2s)", True),
    # §7.3.9.3.3: `equal`, all members start and end at the same time: a member of known
    # length shorter than the first cannot be held (a goal reached early can)
    ("overlap equal: a wait shorter than the first", "parallel(overlap: equal):\n    hero.drive(duration: 2s)\n    wait elapsed(1s)", True),
    ("overlap equal: a goal reached early is held", "parallel(overlap: equal):\n    hero.drive(duration: 2s)\n    hero.change_speed(target: 20kph)", False),
    ("overlap inside: a bounded drive not yet at its lower bound", "parallel(overlap: inside):\n    wait elapsed(2s)\n    hero.drive(duration: 3s)", True),
    ("overlap end: a bounded drive past its lower bound is stopped", "parallel(overlap: end):\n    wait elapsed(2s)\n    hero.drive(duration: [1s..3s])", False),
    ("overlap final: an open-ended drive is stopped", "parallel(overlap: final):\n    wait elapsed(2s)\n    hero.drive()", False),
    ("overlap initial: an open-ended first waits for the others", "serial(duration: 2s):\n    parallel(overlap: initial):\n        hero.drive()\n        wait elapsed(1s)\n    wait elapsed(1s)", False),
    ("overlap equal: an until on an event may end early", "parallel(overlap: equal):\n    wait elapsed(1s)\n    hero.drive() with:\n        until hero.speed > 10kph", False),
    ("overlap equal: an until elapsed ends before the first", "parallel(overlap: equal):\n    wait elapsed(1s)\n    hero.drive() with:\n        until elapsed(0.5s)", True),
    # `end`: all members end at the same time, the longest starting first
    ("overlap end: a longer member starts first", "serial(duration: 5s):\n    parallel(overlap: end):\n        wait elapsed(2s)\n        hero.drive(duration: 5s)", False),
    ("overlap end: the members end together, after the longest", "serial(duration: 4s):\n    parallel(overlap: end):\n        wait elapsed(2s)\n        hero.drive(duration: 5s)", True),
    ("overlap end: a shorter member starts late", "serial(duration: 3s):\n    parallel(overlap: end):\n        wait elapsed(3s)\n        hero.drive(duration: 1s)\n    wait elapsed(0s)", False),
    # `final`: the others end with the first member and start no earlier than it
    ("overlap final: a member longer than the first", "parallel(overlap: final):\n    wait elapsed(2s)\n    hero.drive(duration: 3s)", True),
    ("overlap final: a shorter member starts late", "parallel(overlap: final):\n    wait elapsed(3s)\n    hero.drive(duration: 1s)", False),
    # `full`: the others cover the first member
    ("overlap full: a member shorter than the first", "parallel(overlap: full):\n    wait elapsed(2s)\n    hero.drive(duration: 1s)", True),
    ("overlap full: a member that covers the first", "parallel(overlap: full):\n    wait elapsed(1s)\n    hero.drive(duration: 2s)", False),
    ("overlap equal: an until later than the first", "parallel(overlap: equal):\n    wait elapsed(1s)\n    hero.drive() with:\n        until elapsed(2s)", True),
    # one_of: one acting member, the waiting ones run alongside
    ("one_of ends with its waiting member", "serial(duration: 2s):\n    one_of:\n        hero.drive(duration: 3s)\n        wait elapsed(1s)\n    wait elapsed(1s)", False),
    ("one_of whose waiting member is late", "serial(duration: 2s):\n    one_of:\n        hero.drive(duration: 3s)\n        wait elapsed(1s)\n    wait elapsed(1.5s)", True),
    ("one_of: no acting member fits", "serial(duration: 2s):\n    one_of:\n        hero.drive(duration: 3s)\n        hero.drive(duration: [2.5s..4s])", True),
    ("one_of: a choice that fits", "serial(duration: 2s):\n    one_of:\n        hero.drive(duration: 3s)\n        hero.drive(duration: 1s)\n    wait elapsed(1s)", False),
    # until ends a phase whenever its event occurs
    ("until elapsed ends before the duration's lower bound", "serial(duration: 2s):\n    hero.drive(duration: 5s) with:\n        until elapsed(1s)\n    wait elapsed(1s)", False),
    ("until elapsed later than the serial allows", "serial(duration: 2s):\n    hero.drive() with:\n        until elapsed(1.5s)\n    wait elapsed(1s)", True),
    ("until on an unknown event may end the phase any time", "serial(duration: 2s):\n    hero.drive(duration: 5s) with:\n        until hero.speed > 10kph\n    wait elapsed(1s)", False),
    ("a wait for an event may end any time", "serial(duration: 2s):\n    wait hero.speed > 10kph\n    wait elapsed(2s)", False),
]  # fmt: skip


@pytest.mark.parametrize(("body", "infeasible"), [r[1:] for r in RULES], ids=[r[0] for r in RULES])
def test_rule(body: str, infeasible: bool):
    found = b608(scenario(body))
    assert bool(found) is infeasible, [d.message for d in found]


def test_a_conflict_names_the_durations_that_clash():
    text = scenario(
        "serial(duration: 7.5s):\n"
        "    hero.change_speed(target: 20kph, duration: [4s..6s])\n"
        "    wait elapsed(1s)\n"
        "    hero.change_speed(target: 10kph, duration: [3s..4s])"
    )
    (found,) = b608(text)
    lines = sorted([found.span.line, *(r.span.line for r in found.related)])
    assert lines == [5, 6, 7, 8]  # the serial's and its three members' (8 s at least)
    assert "`serial(duration: 7.5s)`" in found.message


def test_a_conflict_with_a_parameter_names_its_keep():
    text = scenario(
        "serial(duration: 4s):\n    hero.drive(duration: 2s)\n    hero.drive(duration: d)",
        params="d: time\nkeep(d in [3s..5s])",
    )
    (found,) = b608(text)
    assert "`keep(d in [3s..5s])`" in found.message
    assert "`hero.drive(duration: d)`" in found.message


def test_timing_and_placement_share_the_choice_of_a_one_of():
    """Only the second member of the `one_of` fits in the serial's 2 s, and each member
    starts ``hero`` in its own lane: every witness chooses the second member once, for
    the timing and the start placement alike (one choice variable)."""
    text = scenario(
        "serial(duration: 2s):\n"
        "    one_of:\n"
        "        hero.drive(duration: 3s) with:\n"
        "            lane(1, at: start)\n"
        "        hero.drive(duration: 1s) with:\n"
        "            lane(2, at: start)"
    )
    analysis, errors = check(text)
    assert not errors
    for seed in range(6):
        witness = solve(analysis, seed=seed)
        assert isinstance(witness, Witness)
        choices = [p for p in witness.parameters if p.name.startswith("one_of@")]
        assert [(p.name, p.text) for p in choices] == [("one_of@6:9.member", "1")], seed
        hero = witness.actor("hero")
        assert hero is not None and hero.lane == 2, seed


def test_a_parallel_start_offset_is_not_verified():
    text = scenario("parallel(start_to_start: 1s):\n    wait elapsed(1s)\n    wait elapsed(2s)")
    analysis, errors = check(text)
    assert not errors
    assert [str(d.code) for d in analysis.diagnostics if str(d.code) == "C411"] == ["C411"]


def test_a_negative_constant_duration_is_b604_not_b608():
    _, errors = check(scenario("serial(duration: 1s):\n    hero.drive(duration: -2s)"))
    assert [str(d.code) for d in errors] == ["B604"]


@pytest.mark.parametrize("seed", range(5))
def test_the_witness_gives_a_duration_parameter_a_value_that_keeps_the_timing(seed: int):
    from osc2check.verify.api import solve

    text = scenario(
        "serial(duration: 5s):\n"
        "    wait elapsed(1s)\n"
        "    hero.change_speed(target: 20kph, duration: d)\n"
        "    wait elapsed(1s)",
        params="d: time\nkeep(d in [1s..10s])",
    )
    analysis, errors = check(text)
    assert not errors
    witness = solve(analysis, "top", seed=seed)
    value = witness.parameter("d")
    assert value is not None and isinstance(value.value, Fraction)
    assert Fraction(1) <= value.value <= Fraction(3)  # 1 s before it, 1 s after it
    assert not any(timing.is_timing_variable(p.name) for p in witness.parameters)


def test_constant_timing_that_holds_adds_nothing_to_the_problem():
    analysis, errors = check(
        scenario("parallel:\n    hero.drive(duration: 30s)\n    hero.change_speed(target: 20kph)")
    )
    assert not errors
    (result,) = analysis.verified[URI].scenarios
    assert not any(timing.is_timing_variable(n) for n in result.problem.variables)


# ---- conflicts are minimal ------------------------------------------------------------------


def minimal(text: str) -> None:
    """Each B608 conflict of ``text`` is minimal: without any one of its constraints the
    rest of the problem (its other constraints and the definitions) can hold."""
    analysis, _ = check(text)
    (result,) = analysis.verified[URI].scenarios
    assert result.outcome.status == "unsat"
    problem = result.problem
    active = active_constraints(problem, SolverOutcome("sat"))
    definitions = [c for c in active if c.kind == DEFINITION]
    for conflict in result.outcome.conflicts:
        members = [conflict.primary, *conflict.others]
        assert all(c.kind != DEFINITION for c in members)
        for left_out in members:
            ctx = z3.Context()
            enc = Encoder(problem, ctx)
            solver = z3.Solver(ctx=ctx)
            for c in [*definitions, *(m for m in members if m is not left_out)]:
                solver.add(enc.term(c.term))
            assert solver.check() == z3.sat, f"`{left_out.text}` is not needed"
        solver = z3.Solver(ctx=ctx)
        for c in [*definitions, *members]:
            solver.add(enc.term(c.term))
        assert solver.check() == z3.unsat


@pytest.mark.parametrize("body", [r[1] for r in RULES if r[2]], ids=[r[0] for r in RULES if r[2]])
def test_conflicts_are_minimal(body: str):
    minimal(scenario(body))


# ---- the tables shared with the runner ------------------------------------------------------


def test_instant_and_endless_actions_are_the_runners():
    from osc2runner.behaviours.base import InstantAction
    from osc2runner.compile import composites
    from osc2runner.compile.registry import standard_registry

    for entry in standard_registry().actions():
        instant = issubclass(entry.target, InstantAction)
        assert instant is (entry.name in INSTANT_ACTIONS), entry.label
        assert (not entry.target.finite) is (entry.name in ENDLESS_ACTIONS), entry.label
    assert composites.ENDS_WITH_FIRST is ENDS_WITH_FIRST


# ---- against the runner -------------------------------------------------------------------

DURATIONS = ["0.5s", "1s", "1.5s", "2s", "3s"]
RANGES = ["[0.5s..1s]", "[1s..2s]", "[1.5s..3s]"]
OVERLAPS = ["start", "equal", "end", "inside", "initial", "final", "full", "any"]


@st.composite
def durations(draw: st.DrawFn) -> str:
    return draw(st.sampled_from(DURATIONS + RANGES))


@st.composite
def leaves(draw: st.DrawFn) -> list[str]:
    kind = draw(st.sampled_from(["drive", "open", "wait", "until"]))
    if kind == "drive":
        return [f"hero.drive(duration: {draw(durations())})"]
    if kind == "open":
        return ["hero.drive()"]
    if kind == "until":
        return ["hero.drive() with:", f"    until elapsed({draw(st.sampled_from(DURATIONS))})"]
    return [f"wait elapsed({draw(st.sampled_from(DURATIONS))})"]


@st.composite
def members(draw: st.DrawFn, depth: int) -> list[str]:
    if depth == 0 or draw(st.booleans()):
        return draw(leaves())
    op = draw(st.sampled_from(["serial", "parallel", "one_of"]))
    args = []
    if op == "parallel":
        args.append(f"overlap: {draw(st.sampled_from(OVERLAPS))}")
    if op != "one_of" and draw(st.booleans()):
        args.append(f"duration: {draw(durations())}")
    head = op + (f"({', '.join(args)})" if args else "") + ":"
    if op == "one_of":  # one acting member (the runner's seed picks among several)
        inner = [draw(members(depth - 1))]
        inner.append([f"wait elapsed({draw(st.sampled_from(DURATIONS))})"])
    else:
        inner = [draw(members(depth - 1)) for _ in range(draw(st.integers(1, 3)))]
    lines = [head]
    for m in inner:
        lines += [f"    {line}" for line in m]
    return lines


def runner_fails_on_timing(text: str, monkeypatch: pytest.MonkeyPatch) -> bool:
    """Whether the runner fails ``text`` for timing reasons (the checker's timing model is
    left out of the witness, so that the runner runs it whatever the checker says)."""
    from osc2runner.runner import run

    with monkeypatch.context() as patch:
        patch.setattr(timing, "lower_timing", lambda lowerer, scenario: None)
        result = run(URI, source=text, duration=12)
    outcome = result.outcome
    return outcome.status == "failure" and any(k in (outcome.reason or "") for k in TIMING_FAILURES)


CROSS = settings(
    derandomize=True,
    max_examples=30,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@pytest.mark.slow
@CROSS
@given(lines=members(2))
def test_the_checker_reports_b608_exactly_when_the_runner_fails_on_timing(
    lines: list[str], monkeypatch: pytest.MonkeyPatch
):
    text = scenario("\n".join(lines))
    found = b608(text)
    assert bool(found) is runner_fails_on_timing(text, monkeypatch), text


KNOWN = [r for r in RULES if "hero.change" not in r[1] and "hero.speed" not in r[1]]


@pytest.mark.parametrize(("body", "infeasible"), [r[1:] for r in KNOWN], ids=[r[0] for r in KNOWN])
def test_the_runner_agrees_with_each_rule(
    body: str, infeasible: bool, monkeypatch: pytest.MonkeyPatch
):
    assert runner_fails_on_timing(scenario(body), monkeypatch) is infeasible


@pytest.mark.slow
@settings(
    derandomize=True,
    max_examples=60,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(members(2))
def test_every_generated_conflict_is_minimal(lines: list[str]):
    text = scenario("\n".join(lines))
    if b608(text):
        minimal(text)
