"""Enum literals win where an enum is expected (every dialect): a declared event or
global named `start`, `end`, `left`, `right` does not shadow the member in an argument
of enum type; N115 says so."""

from __future__ import annotations

from fractions import Fraction

from osc2check.analysis import SourceInput, analyze
from osc2check.verify.api import solve

CARLA_LIKE = """\
import osc.standard

global left: string = "l"

scenario top:
    hero: vehicle
    npc: vehicle
    event start
    event end
    do parallel(duration: 5s):
        hero.drive() with:
            lane(1, at: start)
            speed(50kph, at: start)
        npc.drive() with:
            lane(side_of: hero, side: left, at: start)
            position(10m, ahead_of: hero, at: start)
"""


def analysed(text: str):
    return analyze([SourceInput("t.osc", text)])


def test_the_member_is_taken_and_each_shadowing_name_is_reported():
    analysis = analysed(CARLA_LIKE)
    found = [(d.span.line, d.code.code) for d in analysis.diagnostics if d.code.code == "N115"]
    assert found == [(12, "N115"), (13, "N115"), (15, "N115"), (15, "N115"), (16, "N115")]
    message = next(d.message for d in analysis.diagnostics if d.span.line == 15)
    assert "`side_left_right!left`" in message and "global parameter" in message


def test_at_start_constrains_the_start_and_side_left_is_the_left_side():
    witness = solve(analysed(CARLA_LIKE), "top")
    hero = witness.actor("hero")
    npc = witness.actor("npc")
    assert hero.speed == Fraction(50) / Fraction("3.6")  # at: start holds at the start
    assert npc.lane == hero.lane + 1  # lanes counted from the right: left is one up
