"""The verification layer: the constraint IR, lowering, the solver, placement and witnesses.

Findings per code are golden cases (``cases/constraints``, ``cases/placement``,
``cases/flow``); this file tests what a golden case cannot show: the override rule and
the lowering's semantics, conflicts spread over several files (JSON and SARIF related
locations), the paper's scenarios and their witnesses, seeds, and the solver's cores on
the IR.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
from fractions import Fraction
from pathlib import Path

import pytest
import z3

import osc2check
from osc2check import cli
from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.verify import ir, propagate
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.terms import in_range
from osc2check.verify.z3_backend import Sampler, SolverOutcome, active_constraints, check, solve

CASES = Path(__file__).resolve().parents[1] / "cases"
SEED_DIR = Path(__file__).resolve().parents[2] / "data" / "seed"  # vendored
THREE_FILES = CASES / "constraints" / "C401_conflict_across_three_files"
KPH = Fraction(5, 18)


def span(line: int, uri: str = "t.osc"):
    from osc2check.source import Span

    return Span(uri, line, 1, line, 2)


def checked(text: str, uri: str = "t.osc", **kw):
    """The analysis of one in-memory file."""
    return analyze([SourceInput(uri, text)], AnalysisOptions(**kw))


def codes_of(analysis) -> list[str]:
    return [d.code.code for d in analysis.diagnostics]


def result_of(text: str, name: str | None = None, **kw):
    analysis = checked(text, **kw)
    results = analysis.verified["t.osc"].scenarios
    return next(r for r in results if name is None or r.scenario.name == name)


def values_of(text: str, **kw) -> dict:
    r = result_of(text, **kw)
    assert r.outcome.status == "sat", r.outcome
    return {p.name: p.value for p in r.witness.parameters}


HEADER = "import osc.standard\n\n"


# --- the IR and the backend ---------------------------------------------------------------


def problem_of(*constraints: tuple[ir.Term, str], variables=()) -> ConstraintProblem:
    p = ConstraintProblem("p", span(1))
    for v in variables:
        p.variables[v.name] = v
    for line, (term, kind) in enumerate(constraints, start=2):
        p.add(ir.Constraint(term, span(line), kind, f"c{line}"))
    return p


def test_solve_reports_a_minimal_core_with_the_last_user_constraint_as_primary():
    x, y = ir.Var("x", "real"), ir.Var("y", "real")
    X, Y = ir.Ref(x), ir.Ref(y)
    p = problem_of(
        (ir.op(">=", X, ir.const(10)), "keep"),
        (ir.op("<=", Y, ir.const(3)), "keep"),  # unrelated
        (ir.op("==", Y, X), "keep"),
        (ir.op(">=", Y, ir.const(0)), "keep"),  # unrelated
        variables=(x, y),
    )
    outcome = solve(p)
    assert outcome.status == "unsat"
    (conflict,) = outcome.conflicts
    assert conflict.primary.span.line == 4
    assert sorted(c.span.line for c in conflict.others) == [2, 3]


def test_check_finds_easy_models_without_z3_and_sends_the_rest_to_it():
    x, n = ir.Var("x", "real"), ir.Var("n", "int")
    X, N = ir.Ref(x), ir.Ref(n)
    easy = problem_of(
        (in_range(X, ir.const(5), ir.const(1)), "keep"),
        (ir.op("==", N, ir.op("+", ir.const(2), ir.const(3))), "keep"),
        variables=(x, n),
    )
    outcome = check(easy)
    assert (outcome.status, outcome.method) == ("sat", "propagation")
    assert 1 <= outcome.values["x"] <= 5 and outcome.values["n"] == 5
    hard = problem_of(
        (ir.op("or", ir.op(">=", X, ir.const(7)), ir.op("<=", X, ir.const(-7))), "keep"),
        (ir.op("!=", X, ir.const(0)), "keep"),
        (ir.op("<=", X, ir.const(-8)), "keep"),
        variables=(x,),
    )
    outcome = check(hard)
    assert outcome.status == "sat" and outcome.values["x"] <= -8
    unsat = problem_of(
        (ir.op(">=", X, ir.const(1)), "keep"), (ir.op("<", X, ir.const(1)), "keep"), variables=(x,)
    )
    assert check(unsat).status == "unsat"


def test_quick_holds_is_true_false_or_none_when_the_term_cannot_be_evaluated():
    x = ir.Var("x", "real")
    positive = ir.op(">", ir.Ref(x), ir.const(0))
    assert propagate.holds(positive, {"x": Fraction(1)}) is True
    assert propagate.holds(positive, {"x": Fraction(-1)}) is False
    assert propagate.holds(positive, {}) is None  # x has no value
    reciprocal = ir.op(">", ir.op("/", ir.const(1), ir.Ref(x)), ir.const(0))
    assert propagate.holds(reciprocal, {"x": 0}) is None
    assert (
        propagate.holds(ir.op("+", ir.Ref(x), ir.const(1)), {"x": Fraction(0)}) is False
    )  # 1, not True


def test_an_integer_equation_with_a_fractional_solution_is_not_a_quick_model():
    n = ir.Var("n", "int")
    terms = [ir.op("==", ir.op("*", ir.const(2), ir.Ref(n)), ir.const(3))]
    assert propagate.find_model({"n": n}, terms) is None
    p = problem_of((terms[0], "keep"), variables=(n,))
    assert check(p).status == "unsat"


def test_ranges_hold_in_either_order_even_with_parameter_bounds():
    x, a, b = ir.Var("x", "real"), ir.Var("a", "real"), ir.Var("b", "real")
    X, A, B = ir.Ref(x), ir.Ref(a), ir.Ref(b)
    p = problem_of(
        (ir.op("==", A, ir.const(9)), "keep"),
        (ir.op("==", B, ir.const(2)), "keep"),
        (in_range(X, A, B), "keep"),
        (ir.op("==", X, ir.const(4)), "keep"),
        variables=(x, a, b),
    )
    assert solve(p).status == "sat"


FLOW = """\
import osc.standard

scenario top:
    hero: vehicle
    event stop_signal
    do serial:
        hero.drive(duration: 2s) with:
            lane(1, at: start)
        wait @stop_signal
"""


@pytest.mark.parametrize("verify", [True, False])
def test_flow_findings_come_once_with_or_without_the_solver(verify: bool):
    # the flow needs no solver: the editor's analysis between keystrokes has it too
    analysis = analyze([SourceInput("flow.osc", FLOW)], AnalysisOptions(verify=verify))
    assert [(str(d.code), d.span.line) for d in analysis.diagnostics] == [("B601", 9)]
    assert ("flow.osc" in analysis.verified) is verify


def test_override_rule_on_the_ir():
    """A default yields to a hard `==`/`in` on its parameter alone and to remove_default."""
    x, y, z_ = ir.Var("x", "real"), ir.Var("y", "real"), ir.Var("z", "real")
    p = ConstraintProblem("p", span(1))
    for v in (x, y, z_):
        p.variables[v.name] = v
    dx = ir.Constraint(ir.op("==", ir.Ref(x), ir.const(1)), span(2), "default", "dx", "default", x)
    hx = ir.Constraint(ir.op("==", ir.Ref(x), ir.const(2)), span(3), "keep", "hx", "hard", x)
    dy = ir.Constraint(ir.op("==", ir.Ref(y), ir.const(1)), span(4), "default", "dy", "default", y)
    hy = ir.Constraint(ir.op("<=", ir.Ref(y), ir.const(0)), span(5), "keep", "hy", "hard", None)
    dz = ir.Constraint(
        ir.op("==", ir.Ref(z_), ir.const(1)), span(6), "default", "dz", "default", z_
    )
    p.constraints = [dx, hx, dy, hy, dz]
    p.removed_defaults.add("z")
    outcome = SolverOutcome("sat")
    active = active_constraints(p, outcome)
    assert active == [hx, dy, hy]
    assert outcome.overridden == [(dx, hx), (dz, None)]
    assert solve(p).status == "unsat"  # `y <= 0` does not override `default y == 1`


# --- lowering: the standard's semantics through OSC2 text ---------------------------------


def test_a_more_specific_default_wins_and_the_field_value_is_the_first_default():
    text = (
        HEADER
        + """actor robot inherits vehicle:
    reach: length = 5m
    keep(default reach == 6m)

scenario s:
    hero: robot with:
        keep(default it.reach == 7m)
    plain: robot
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
"""
    )
    values = values_of(text)
    assert values["hero.reach"] == 7
    assert values["plain.reach"] == 6
    analysis = checked(text)
    c404 = [d for d in analysis.diagnostics if d.code.code == "C404"]
    assert [(d.span.line, d.message) for d in c404] == [
        (
            5,
            "`keep(default reach == 6m)` gives the parameter another default than "
            "`reach: length = 5m`; the later one wins",
        )
    ]
    assert "C403" not in codes_of(analysis)


def test_an_argument_overrides_the_default_of_its_parameter():
    text = (
        HEADER
        + """scenario cruise:
    car: vehicle
    target: speed = 50kph
    do car.drive(duration: 10s) with:
        lane(1, at: start)

scenario top:
    hero: vehicle
    do serial:
        hero.drive(duration: 1s) with:
            lane(1, at: start)
        cruise(car: hero, target: 70kph)
"""
    )
    r = result_of(text, "top")
    assert r.outcome.status == "sat"
    (value,) = [v for k, v in r.outcome.values.items() if k.endswith(".target")]
    assert value == 70 * KPH


def test_a_fraction_given_to_an_integer_parameter_is_truncated_not_a_conflict():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    do hero.drive(duration: 10s) with:
        lane(2.7, at: start)
"""
    )
    analysis = checked(text)
    assert codes_of(analysis) == ["T204"]
    witness = analysis.verified["t.osc"].scenarios[0].witness
    assert witness.actor("hero").lane == 2


def test_a_reversed_range_with_parameter_bounds_is_the_range_between_them():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    low: speed
    high: speed
    v: speed
    keep(low == 50kph)
    keep(high == 30kph)
    keep(v in [low..high])
    keep(v == 40kph)
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
"""
    )
    assert "C401" not in codes_of(checked(text))


def test_messages_quote_the_constraint_without_its_comment():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    v: speed
    keep(v > 60kph)   # faster than the band
    keep(v in [30kph..50kph])
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
"""
    )
    (d,) = checked(text).diagnostics
    assert d.code.code == "C401"
    assert d.message == (
        "constraints of scenario `s` cannot all hold: "
        "`keep(v in [30kph..50kph])`; `keep(v > 60kph)`"
    )
    assert [(r.span.line, r.message) for r in d.related] == [
        (6, "conflicts with `keep(v > 60kph)`")
    ]


# --- placement conventions -----------------------------------------------------------------


def start_of(text: str, seed: int = 0):
    analysis = checked(text, seed=seed)
    assert not [d for d in analysis.diagnostics if d.severity.name == "ERROR"], analysis.diagnostics
    return analysis.verified["t.osc"].scenarios[0].witness


def test_gap_is_bumper_to_bumper_and_time_headway_uses_the_followers_speed():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    npc: vehicle
    do parallel:
        hero.drive(duration: 10s) with:
            lane(1, at: start)
            speed(36kph, at: start)
        npc.drive(duration: 10s) with:
            lane(1, at: start)
            speed(72kph, at: start)
            position(time: 2s, behind: hero, at: start)
"""
    )
    w = start_of(text)
    hero, npc = w.actor("hero"), w.actor("npc")
    gap = (hero.s - hero.length / 2) - (npc.s + npc.length / 2)
    assert gap == 40  # 2 s at the follower's (npc's) 20 m/s


def test_relative_speed_uses_the_factor_and_lanes_can_count_from_the_left():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    npc: vehicle
    do parallel:
        hero.drive(duration: 10s) with:
            lane(1, at: start)
            speed(40kph, at: start)
        npc.drive(duration: 10s) with:
            lane(1, from: left, at: start)
            speed(10kph, faster_than: hero, factor: 1.5, at: start)
"""
    )
    w = start_of(text)
    assert w.actor("npc").speed == 70 * KPH
    assert (w.actor("hero").lane, w.actor("npc").lane) == (1, 3)


def test_on_town06_lanes_count_from_the_left_and_right_of_lane_1_is_lane_2():
    text = (
        HEADER
        + """scenario s:
    town: map with:
        keep(it.map_file == "Town06")
    hero: vehicle
    npc: vehicle
    do parallel:
        hero.drive(duration: 10s) with:
            lane(1, at: start)
        npc.drive(duration: 10s) with:
            lane(side_of: hero, side: right, at: start)
"""
    )
    w = start_of(text)
    assert (w.map, w.lane_numbering) == ("Town06", "from_left")
    assert (w.actor("hero").lane, w.actor("npc").lane) == (1, 2)
    assert w.actor("npc").y < w.actor("hero").y  # right of the hero


def test_at_all_modifiers_of_the_first_invocation_hold_at_the_start_unless_given_explicitly():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    do serial:
        hero.drive(duration: 10s) with:
            lane(2)
            speed(30kph)
            speed(0kph, at: start)
        hero.drive(duration: 10s) with:
            lane(3)
"""
    )
    w = start_of(text)
    assert (w.actor("hero").lane, w.actor("hero").speed) == (2, 0)


ONE_OF_STARTS = (
    HEADER
    + """scenario s:
    hero: vehicle
    do one_of:
        hero.drive(duration: 10s) with:
            lane(1, at: start)
        hero.drive(duration: 10s) with:
            lane(2, at: start)
"""
)


def test_one_of_members_are_placed_for_the_member_the_witness_chooses():
    assert codes_of(checked(ONE_OF_STARTS)) == []
    lanes = {}
    for seed in range(4):
        w = start_of(ONE_OF_STARTS, seed=seed)
        member = w.parameter("one_of@5:8.member")
        assert member is not None
        lanes[int(member.value)] = w.actor("hero").lane
    assert lanes == {0: 1, 1: 2}  # both members drawn, each placed as it asks


def test_one_of_members_none_of_which_can_be_placed_are_a_conflict():
    text = ONE_OF_STARTS.replace("lane(1, at: start)", "lane(7, at: start)").replace(
        "lane(2, at: start)", "lane(9, at: start)"
    )
    (found,) = checked(text).diagnostics
    assert found.code.code == "L503"
    assert "`lane(7, at: start)`" in found.message and "`lane(9, at: start)`" in found.message
    assert "one member of the `one_of` (1 to 2) runs" in found.message


def test_one_of_member_that_cannot_be_placed_is_never_drawn():
    text = ONE_OF_STARTS.replace("lane(1, at: start)", "lane(7, at: start)")
    for seed in range(3):
        w = start_of(text, seed=seed)
        assert (w.parameter("one_of@5:8.member").value, w.actor("hero").lane) == (1, 2)


def test_placement_takes_the_do_the_scenario_runs_an_inherited_one_too():
    # b runs a's `do` (as the runner compiles it): its lane 5 is L503 for b as for a;
    # c's own `do` replaces a's, so a's lane 5 is not c's.
    text = (
        HEADER
        + """scenario a:
    hero: vehicle
    do hero.drive(duration: 10s) with:
        lane(5, at: start)
        speed(50kph)

scenario b inherits a:
    x: int = 1

scenario c inherits a:
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
        speed(50kph)
"""
    )
    analysis = checked(text)
    found = sorted(
        (d.code.code, d.span.line, d.message.split("`")[1]) for d in analysis.diagnostics
    )
    assert found == [("L503", 6, "a"), ("L503", 6, "b")]
    results = {r.scenario.name: r for r in analysis.verified["t.osc"].scenarios}
    assert {n: r.outcome.status for n, r in results.items()} == {
        "a": "unsat",
        "b": "unsat",
        "c": "sat",
    }
    assert results["c"].witness.actor("hero").lane == 1


def test_a_lateral_offset_may_leave_the_lane_but_not_the_road():
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    do hero.drive(duration: 10s) with:
        lane(2, at: start)
        lateral(distance: 1m, at: start)
"""
    )
    assert start_of(text).actor("hero").t == 1


# --- a conflict over three files -------------------------------------------------------------


def run(argv: list[str], cwd: Path) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.chdir(cwd), contextlib.redirect_stdout(out):
        status = cli.main(argv)
    return status, out.getvalue()


def test_a_conflict_over_three_files_is_reported_with_every_line_in_json():
    status, out = run(  # A308 (`route`'s actor `bus` not passed) is beside the point
        ["main.osc", "--isolated", "--ignore", "A308", "--output-format", "json"], THREE_FILES
    )
    assert status == 1
    document = json.loads(out)
    (finding,) = document["findings"]
    assert finding["code"] == "C401"
    assert finding["location"]["path"] == "main.osc"
    assert finding["location"]["start"] == {"line": 6, "column": 14}
    related = sorted(
        (os.path.normpath(r["path"]), r["start"]["line"], r["message"]) for r in finding["related"]
    )
    assert related == [
        (os.path.join("lib", "shuttle.osc"), 6, "conflicts with `keep(cruise <= 60kph)`"),
        (os.path.join("scenarios", "route.osc"), 8, "conflicts with `keep(target == bus.cruise)`"),
    ]
    # the default that the hard keep replaces is not part of the conflict
    assert "50kph" not in finding["message"]
    (scenario,) = document["scenarios"]
    assert (scenario["name"], scenario["status"], scenario["conflicts"]) == (
        "rush_hour",
        "unsat",
        1,
    )


def test_a_conflict_over_three_files_carries_related_locations_in_sarif():
    status, out = run(  # A308 (`route`'s actor `bus` not passed) is beside the point
        ["main.osc", "--isolated", "--ignore", "A308", "--output-format", "sarif"], THREE_FILES
    )
    assert status == 1
    (result,) = json.loads(out)["runs"][0]["results"]
    assert result["ruleId"] == "C401"
    lines = sorted(
        (
            os.path.normpath(r["physicalLocation"]["artifactLocation"]["uri"]),
            r["physicalLocation"]["region"]["startLine"],
        )
        for r in result["relatedLocations"]
    )
    assert lines == [
        (os.path.join("lib", "shuttle.osc"), 6),
        (os.path.join("scenarios", "route.osc"), 8),
    ]


def test_a_conflict_inside_imported_files_is_reported_at_the_scenario(tmp_path: Path):
    (tmp_path / "lib.osc").write_text(
        HEADER
        + """scenario capped:
    car: vehicle
    v: speed
    keep(v <= 50kph)
    keep(v >= 60kph)
    do car.drive(duration: 10s)
"""
    )
    (tmp_path / "main.osc").write_text(
        HEADER
        + """import "lib.osc"

scenario top:
    do capped()
"""
    )
    status, out = run(["main.osc", "--isolated", "--output-format", "json"], tmp_path)
    (finding,) = [f for f in json.loads(out)["findings"] if f["code"] == "C401"]
    assert (finding["location"]["path"], finding["location"]["start"]["line"]) == ("main.osc", 5)
    assert sorted(r["start"]["line"] for r in finding["related"]) == [6, 7]


# --- the paper's scenarios ---------------------------------------------------------------------

PAPER = sorted(SEED_DIR.glob("*.osc"))


@pytest.mark.parametrize("path", PAPER, ids=lambda p: p.stem)
def test_the_papers_scenarios_check_without_errors(path: Path):
    analysis = analyze([SourceInput(str(path), path.read_text())])
    errors = [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    assert errors == []
    assert [r.outcome.status for r in analysis.verified[str(path)].scenarios] == ["sat"]


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 7, 42])
def test_the_cut_in_witness_puts_the_npc_5m_behind_and_one_lane_right(seed: int):
    path = SEED_DIR / "cut_in_and_stop.osc"
    analysis = osc2check.analyze([SourceInput(str(path), path.read_text())])
    witness = osc2check.solve(analysis, seed=seed)
    assert (witness.map, witness.lane_numbering) == ("Town06", "from_left")
    hero, npc = witness.actor("hero"), witness.actor("npc")
    assert (hero.lane, npc.lane) == (1, 2)
    assert (hero.s - hero.length / 2) - (npc.s + npc.length / 2) == 5
    assert npc.category == "truck" and npc.length == 12
    assert hero.speed == npc.speed == 0
    assert witness.parameter("safety_gap").value == 12


def test_the_braking_witness_starts_the_hero_standing_in_lane_1():
    path = SEED_DIR / "braking_friction.osc"
    analysis = osc2check.analyze([SourceInput(str(path), path.read_text())])
    for seed in (0, 5):
        hero = osc2check.solve(analysis, seed=seed).actor("hero")
        assert (hero.lane, hero.speed) == (1, 0)


# --- seeds ---------------------------------------------------------------------------------------

FREE_RANGE = (
    HEADER
    + """scenario s:
    hero: vehicle
    cruise: speed
    keep(cruise in [30kph..120kph])
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
        speed(cruise)
"""
)


def test_seeds_spread_witnesses_and_the_same_seed_gives_the_same_witness():
    analysis = osc2check.analyze([SourceInput("t.osc", FREE_RANGE)])
    cruise = [osc2check.solve(analysis, seed=s).parameter("cruise").value for s in range(10)]
    assert len(set(cruise)) >= 5
    assert all(30 * KPH <= v <= 120 * KPH for v in cruise)
    low, high = min(cruise), max(cruise)
    assert high - low >= 30 * KPH  # spread over the range, not clustered at a vertex
    again = [osc2check.solve(analysis, seed=s).parameter("cruise").value for s in range(10)]
    assert again == cruise
    other = osc2check.analyze([SourceInput("t.osc", FREE_RANGE)], AnalysisOptions(seed=3))
    assert (
        other.verified["t.osc"].scenarios[0].witness.to_json()
        == osc2check.solve(analysis, seed=3).to_json()
    )


def test_a_witness_does_not_depend_on_the_other_scenarios_of_the_file():
    other = (
        HEADER
        + """scenario before:
    car: vehicle
    a: speed
    b: speed
    keep(a <= b)
    do car.drive(duration: 1s) with:
        lane(2, at: start)
"""
    )
    alone = osc2check.analyze([SourceInput("t.osc", FREE_RANGE)])
    both = osc2check.analyze([SourceInput("t.osc", other + FREE_RANGE[len(HEADER) :])])

    def shown(witness):  # invocations are named by their line, which moved
        data = witness.to_json()
        return data["actors"], [p["text"] for p in data["parameters"]]

    for seed in (0, 4):
        assert shown(osc2check.solve(alone, "s", seed=seed)) == shown(
            osc2check.solve(both, "s", seed=seed)
        )


def test_start_positions_spread_over_the_first_part_of_the_road():
    """Free starts are spread, and drawn near the road's entry: room to drive ahead."""
    text = (
        HEADER
        + """scenario s:
    hero: vehicle
    do hero.drive(duration: 10s) with:
        lane(1, at: start)
"""
    )
    analysis = osc2check.analyze([SourceInput("t.osc", text)])
    starts = [osc2check.solve(analysis, seed=s).actor("hero").s for s in range(10)]
    assert len(set(starts)) == 10
    assert max(starts) - min(starts) > 150
    assert max(starts) <= 2.25 + (1000 - 4.5) * 0.3  # PREFERRED_START_SHARE of the road


def test_samples_reuse_one_optimizer_and_keep_free_variables_in_their_bounds():
    x, y, free = ir.Var("x", "real"), ir.Var("y", "int"), ir.Var("free", "real")
    p = problem_of(
        (in_range(ir.Ref(x), ir.const(0), ir.const(100)), "keep"),
        (ir.op(">=", ir.Ref(y), ir.op("+", ir.Ref(x), ir.const(3))), "keep"),
        (ir.op("<=", ir.Ref(y), ir.const(200)), "keep"),
        variables=(x, y, free),
    )
    first = solve(p, seed=1).values
    from osc2check.verify.z3_backend import Encoder

    enc = Encoder(p, z3.Context())
    active = active_constraints(p, SolverOutcome("sat"))
    sampler = Sampler(p, active, first, enc=enc)
    samples = [sampler.sample(seed) for seed in range(8)]
    assert all(s is not None and 0 <= s["x"] <= 100 and s["y"] >= s["x"] + 3 for s in samples)
    assert len({s["x"] for s in samples}) == 8
    assert sampler.sample(3) == samples[3]
