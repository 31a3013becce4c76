"""Starts the scenario leaves open, read so that its actions can be done (tentative
constraints: ``ir.Constraint.tentative``, ``ConstraintProblem.firm``). Each reading holds
when the scenario allows it; one that takes part in a conflict gives way, no conflict is
reported for it, and the witness says so.

* After the scenario's first wait (``placement._after_waits``): when nothing acts at
  time 0 and the scenario first waits a constant time, the witness places the actors
  so that the ``at: start`` modifiers of what begins then hold, every actor having kept
  its start lane and speed while it waited.
* A first ``change_lane`` of a car nothing gives a speed: it starts driving.
* A ``change_space_gap`` (or ``_headway``) behind or ahead of a reference that begins at
  time 0: the actor starts on that side, from where driving forward reaches the gap.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify import ir
from osc2check.verify.api import solve
from osc2check.verify.bins import bin_status, witness_in
from osc2check.verify.domains import domains
from osc2check.verify.witness import Witness

URI = "open.osc"
L506_NPC = (
    "nothing that begins at time 0 places `npc`; the solver picks its start (see `--witness`)"
)


def _scenario(wait: str, hero_speed: str, npc_speed: str, gap: str, npc_lane: int = 1) -> str:
    return f"""\
import osc.standard

scenario late:
    hero: vehicle
    npc: vehicle
    do serial:
        wait elapsed({wait})
        parallel(duration: 10s):
            hero.drive() with:
                lane(1, at: start)
                speed({hero_speed})
            npc.drive() with:
                lane({npc_lane}, at: start)
                position(distance: {gap}, behind: hero, at: start)
                speed({npc_speed}, at: start)
"""


def _analysed(text: str):
    analysis = analyze([SourceInput(URI, text)])
    found = [(d.code.code, d.message) for d in analysis.diagnostics if d.span.uri == URI]
    return analysis, found


def _witness(text: str, seed: int = 0, scenario: str = "late") -> Witness:
    analysis, found = _analysed(text)
    assert not [f for f in found if f[0][0] in "LC" and f[0] != "L506"], found  # L506: info
    witness = solve(analysis, scenario, seed, URI)
    assert isinstance(witness, Witness), witness
    return witness


@pytest.mark.parametrize(
    ("wait", "delay", "hero", "npc", "v_hero", "v_npc"),
    [
        ("2s", 2, "50kph", "50kph", Fraction(125, 9), Fraction(125, 9)),
        ("3s", 3, "50kph", "80kph", Fraction(125, 9), Fraction(200, 9)),
        ("1500ms", Fraction(3, 2), "60kph", "40kph", Fraction(50, 3), Fraction(100, 9)),
    ],
)
@pytest.mark.parametrize("seed", [0, 3])
def test_the_start_after_the_wait_holds_when_every_actor_keeps_its_speed(
    wait, delay, hero, npc, v_hero, v_npc, seed
):
    w = _witness(_scenario(wait, hero, npc, "25m"), seed)
    h, n = w.actor("hero"), w.actor("npc")
    assert h is not None and n is not None
    assert (h.lane, n.lane) == (1, 1)
    assert (h.speed, n.speed) == (v_hero, v_npc)
    h_then, n_then = h.s + delay * h.speed, n.s + delay * n.speed
    assert h_then - n_then - (h.length + n.length) / 2 == 25  # the gap when the wait ends
    assert h.s - n.s >= (h.length + n.length) / 2  # and no overlap on the way there
    assert not w.notes


def test_a_start_that_keeping_speed_cannot_bring_about_gives_way():
    # npc 50 kph slower, 20 m behind after 4 s: it would have started ahead of the hero in
    # its lane and driven through it. The runner prepares that start during the wait.
    analysis, found = _analysed(_scenario("4s", "80kph", "30kph", "20m"))
    assert not [f for f in found if f[0][0] in "LC"], found
    w = solve(analysis, "late", 0, URI)
    assert isinstance(w, Witness)
    assert any("as if every actor kept its start lane and speed" in note for note in w.notes)


def test_the_phase_limits_after_the_wait_still_hold():
    # the tentative reading giving way never drops the lanes the road must have
    _, found = _analysed(_scenario("2s", "50kph", "50kph", "25m", npc_lane=9))
    assert "L503" in {code for code, _ in found}, found


def test_a_wait_the_witness_draws_leaves_the_starts_to_the_runner():
    # a wait as long as a parameter in a range: the starts are not placed for one length
    text = _scenario("pause", "50kph", "50kph", "25m").replace(
        "    npc: vehicle\n",
        "    npc: vehicle\n    pause: time with:\n        keep(it in [2s..4s])\n",
    )
    _, found = _analysed(text)
    assert "L506" in {code for code, _ in found}, found


# ---- after the first wait of a member of the scenario's `parallel`


def _branch(
    hero_speed: str, npc_speed: str, gap: str, npc_first: str = "", hero_at: str = "100m"
) -> str:
    """``hero`` drives from time 0; a member of the ``parallel`` waits 3 s, then places
    ``npc`` (``npc_first``: an action of ``npc`` beside the hero's from time 0)."""
    return f"""\
import osc.standard

scenario late:
    hero: vehicle
    npc: vehicle
    do parallel(duration: 10s):
        hero.drive() with:
            lane(1, at: start)
            position(distance: {hero_at}, at: start)
            speed({hero_speed})
{npc_first}        serial:
            wait elapsed(3s)
            npc.drive() with:
                lane(2, at: start)
                position(distance: {gap}, ahead_of: hero, at: start)
                speed({npc_speed}, at: start)
"""


@pytest.mark.parametrize("seed", [0, 3])
def test_the_start_after_a_members_wait_holds_while_another_member_drives(seed):
    w = _witness(_branch("50kph", "60kph", "25m"), seed)
    h, n = w.actor("hero"), w.actor("npc")
    assert h is not None and n is not None
    assert (h.lane, n.lane) == (1, 2)
    assert (h.speed, n.speed) == (Fraction(125, 9), Fraction(50, 3))
    n_then, h_then = n.s + 3 * n.speed, h.s + 3 * h.speed
    assert n_then - h_then - (h.length + n.length) / 2 == 25
    assert not w.notes


NESTED = """\
import osc.standard

scenario late:
    hero: vehicle
    npc: vehicle
    do serial:
        first: parallel(duration: 10s):
            hero.drive() with:
                lane(1, at: start)
                position(distance: 100m, at: start)
                speed(50kph)
            serial:
                wait elapsed(3s)
                npc.drive() with:
                    lane(2, at: start)
                    position(distance: 25m, ahead_of: hero, at: start)
                    speed(60kph, at: start)
        next: hero.drive(duration: 2s)
"""


def test_a_members_wait_in_the_first_phase_of_a_serial_places_what_begins_then():
    w = _witness(NESTED)
    h, n = w.actor("hero"), w.actor("npc")
    assert h is not None and n is not None and n.lane == 2
    assert n.s + 3 * n.speed - (h.s + 3 * h.speed) - (h.length + n.length) / 2 == 25


def test_each_member_that_first_waits_places_what_begins_when_its_wait_ends():
    text = _branch("50kph", "60kph", "25m").replace(
        "    npc: vehicle\n", "    npc: vehicle\n    van: vehicle\n"
    )
    text += (
        "        serial:\n"
        "            wait elapsed(5s)\n"
        "            van.drive() with:\n"
        "                lane(3, at: start)\n"
        "                position(distance: 15m, behind: npc, at: start)\n"
        "                speed(40kph, at: start)\n"
    )
    w = _witness(text)
    n, v = w.actor("npc"), w.actor("van")
    assert n is not None and v is not None and (n.lane, v.lane) == (2, 3)
    assert n.s + 5 * n.speed - (v.s + 5 * v.speed) - (n.length + v.length) / 2 == 15
    assert not w.notes


def test_a_members_wait_reading_that_cannot_hold_gives_way():
    # npc 100 kph faster and 20 m ahead of the hero after 3 s: it would have started
    # about 50 m before the road's start (the hero starts at 10 m). The reading gives
    # way: no conflict of its own making is reported, and the witness says so.
    analysis, found = _analysed(_branch("30kph", "130kph", "20m", hero_at="10m"))
    assert not [f for f in found if f[0][0] in "LC"], found
    w = solve(analysis, "late", 0, URI)
    assert isinstance(w, Witness)
    said = "first wait of a member of the `parallel` the scenario begins with"
    assert any(said in note for note in w.notes)


def test_an_actor_a_time_0_action_commands_is_not_placed_by_the_reading():
    # npc also drives from time 0 in another member: that action says its state while
    # the member waits, so the reading leaves its start alone (its lane is the seed's)
    npc_first = "        npc.drive(duration: 1s)\n"
    _, found = _analysed(_branch("50kph", "60kph", "25m", npc_first))
    assert ("L506", L506_NPC) in found, found
    lanes = set()
    for seed in range(6):
        n = _witness(_branch("50kph", "60kph", "25m", npc_first), seed).actor("npc")
        assert n is not None
        lanes.add(n.lane)
    assert lanes != {2}


# ---- a first lane change, and a gap to reach


LANE_CHANGE = """\
import osc.standard

scenario swerve:
    ego: vehicle
    do ego.change_lane(side: lane_change_side!left, num_of_lanes: 1)
"""


@pytest.mark.parametrize("seed", range(4))
def test_a_car_whose_first_action_is_a_lane_change_starts_driving(seed):
    # a lane change goes sideways only while the car drives; at rest it never ends
    ego = _witness(LANE_CHANGE, seed, "swerve").actor("ego")
    assert ego is not None and ego.speed >= Fraction(25, 3)  # 30 kph


def test_a_lane_change_of_a_car_the_scenario_stops_starts_it_at_rest():
    text = LANE_CHANGE.replace(
        "num_of_lanes: 1)", "num_of_lanes: 1) with:\n        speed(0kph, at: start)"
    )
    w = _witness(text, 0, "swerve")
    ego = w.actor("ego")
    assert ego is not None and ego.speed == 0
    assert not w.notes  # a written start speed: no reading to give way


def _gap(direction: str, placed: str = "") -> str:
    return f"""\
import osc.standard

scenario close_up:
    ego: vehicle
    lead: vehicle
    do gap: ego.change_space_gap(target: 20m, direction: gap_direction!{direction},
            reference: lead){placed}
"""


@pytest.mark.parametrize("seed", range(4))
def test_a_gap_to_reach_behind_a_reference_starts_further_back(seed):
    w = _witness(_gap("behind"), seed, "close_up")
    ego, lead = w.actor("ego"), w.actor("lead")
    assert ego is not None and lead is not None
    assert lead.s - ego.s - (ego.length + lead.length) / 2 >= 20


@pytest.mark.parametrize("seed", range(4))
def test_a_gap_to_reach_ahead_of_a_reference_starts_within_it(seed):
    w = _witness(_gap("ahead"), seed, "close_up")
    ego, lead = w.actor("ego"), w.actor("lead")
    assert ego is not None and lead is not None
    assert 0 <= ego.s - lead.s - (ego.length + lead.length) / 2 <= 20


def test_a_gap_reading_the_scenario_contradicts_gives_way():
    placed = " with:\n        position(distance: 50m, ahead_of: lead, at: start)"
    w = _witness(_gap("behind", placed), 0, "close_up")
    ego, lead = w.actor("ego"), w.actor("lead")
    assert ego is not None and lead is not None and ego.s > lead.s
    assert any("from where driving forward reaches the gap" in n for n in w.notes), w.notes


TWO_READINGS = """\
import osc.standard

scenario two:
    ego: vehicle
    npc: vehicle
    do parallel:
        ego.change_lane(side: lane_change_side!left, num_of_lanes: 1)
        npc.change_space_gap(target: 20m, direction: gap_direction!behind, reference: ego) with:
            position(distance: 30m, ahead_of: ego, at: start)
"""


@pytest.mark.parametrize("seed", range(3))
def test_only_the_reading_in_a_conflict_gives_way(seed):
    # the npc is written ahead of the ego: its gap reading gives way; the ego, changing
    # lanes first, still starts driving
    w = _witness(TWO_READINGS, seed, "two")
    ego, npc = w.actor("ego"), w.actor("npc")
    assert ego is not None and npc is not None
    assert npc.s > ego.s and ego.speed >= Fraction(25, 3)
    assert len(w.notes) == 1 and "`npc` is placed behind `ego`" in w.notes[0], w.notes


def test_a_coverage_bin_the_scenario_allows_is_reachable_whatever_the_readings():
    # a campaign's bin of the car's start speed below 10 kph: the scenario allows it, and
    # the car that changes lanes first then starts slow, its reading giving way
    analysis, _ = _analysed(LANE_CHANGE)
    (result,) = analysis.verified[URI].scenarios
    speed = result.problem.variables["ego@start.speed"]
    slow = ir.op("<", ir.Ref(speed), ir.const(Fraction(25, 9)))
    assert bin_status(result.problem, slow) == "reachable"
    w = witness_in(result.problem, slow, 0)
    assert w is not None
    ego = w.actor("ego")
    assert ego is not None and ego.speed < Fraction(25, 9)
    assert any("starts at 30 kph or more" in n for n in w.notes), w.notes


def test_a_campaigns_domains_are_what_the_scenario_allows_not_the_readings():
    analysis, _ = _analysed(LANE_CHANGE)
    (result,) = analysis.verified[URI].scenarios
    assert domains(result.problem)["ego@start.speed"].low == 0
