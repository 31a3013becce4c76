"""The road's implicit constraints on a start, as solver terms over carriageways.

Placement gives each actor a lane number, a position ``s`` and an offset ``t``
(``placement``); on a map those are taken on a carriageway
(:mod:`osc2check.world.carriageways`: the driving lanes of one road and
direction, continued across road links), and an actor on a map with several
carriageways also gets a variable saying which one (``<actor>@start.road``, an
index into the map's carriageways). Every term here is linear: a choice among
carriageways and lane sections is a disjunction over them, so the solver picks
the discrete candidate (carriageway, lane) and the continuous ``s`` together.

A map with one carriageway (the built-in straight roads) gets exactly the
constraints and texts of a single straight road: the actor stands within the
road's length, its lane within ``1..n``.
"""

from __future__ import annotations

from fractions import Fraction

from osc2check.verify import ir
from osc2check.world.carriageways import Carriageway, LanePiece

__all__ = ["RoadTerms", "fraction"]


def fraction(value: float) -> Fraction:
    """A map length as an exact number (to the micrometre; map data is floating point)."""
    return Fraction(value).limit_denominator(1_000_000)


class RoadTerms:
    """Terms of one map for placement (see the module docstring).

    Parameters:
        carriageways: the map's (``world.carriageways``).
        name: how messages name it (``default``, ``rural_curves``).
    """

    def __init__(self, carriageways: tuple[Carriageway, ...], name: str) -> None:
        self.name = name
        self.carriageways = carriageways
        self.single = len(self.carriageways) == 1
        self.most_lanes = max((cw.most_lanes for cw in self.carriageways), default=0)
        self.longest = max((cw.length for cw in self.carriageways), default=0.0)
        # every stretch of every carriageway has the same number of lanes
        self.uniform = len({p.count for cw in self.carriageways for p in cw.pieces}) == 1

    # ---- the choice of carriageway

    @staticmethod
    def on(road: ir.Var | None, cw: Carriageway) -> ir.Term:
        return ir.TRUE if road is None else ir.op("==", ir.Ref(road), ir.const(cw.index))

    @staticmethod
    def same(a: ir.Var | None, b: ir.Var | None) -> ir.Term | None:
        """Two actors on one carriageway (None when that is always so)."""
        if a is None or b is None:
            return None
        return ir.op("==", ir.Ref(a), ir.Ref(b))

    @staticmethod
    def apart(a: ir.Var | None, b: ir.Var | None) -> ir.Term | None:
        """Two actors on different carriageways (None when that cannot be)."""
        if a is None or b is None:
            return None
        return ir.op("!=", ir.Ref(a), ir.Ref(b))

    def _any(self, road: ir.Var | None, each: list[tuple[Carriageway, ir.Term]]) -> ir.Term:
        terms = [_and(self.on(road, cw), term) for cw, term in each]
        return terms[0] if len(terms) == 1 else ir.op("or", *terms)

    # ---- where an actor may stand

    def extent(self, road: ir.Var | None, s: ir.Term, half: ir.Term) -> ir.Term:
        """The actor's footprint lies within its carriageway's length."""
        return self._any(
            road,
            [
                (cw, ir.op("and", ir.op(">=", s, half), ir.op("<=", s, _minus(cw.length, half))))
                for cw in self.carriageways
            ],
        )

    def extent_text(self, actor: str, size: str) -> str:
        if self.single:
            cw = self.carriageways[0]
            return f"`{actor}` ({size}) stands on the {cw.length:g} m road `{self.name}`"
        return f"`{actor}` ({size}) stands on a road of map `{self.name}`"

    def lanes(self, road: ir.Var | None, lane: ir.Term, s: ir.Term, phase: bool = False) -> ir.Term:
        """The lane number is one the carriageway has where the actor is (``phase``: one
        some road of the map has: a later phase may be anywhere)."""
        if phase or self.uniform:
            return between(lane, 1, self.most_lanes)
        return self._any(
            road,
            [
                (cw, _and(_within(s, p), between(lane, 1, p.count)))
                for cw in self.carriageways
                for p in cw.pieces
                if p.count > 0
            ],
        )

    def wide(self, road: ir.Var | None, s: ir.Term, lanes: ir.Term) -> ir.Term:
        """The carriageway has at least ``lanes`` driving lanes where the actor is."""
        return self._any(
            road,
            [
                (cw, _and(_within(s, p), ir.op("<=", lanes, ir.const(p.count))))
                for cw in self.carriageways
                for p in cw.pieces
                if p.count > 0
            ],
        )

    def before_junction(
        self, road: ir.Var | None, s: ir.Term, low: ir.Term, high: ir.Term
    ) -> ir.Term | None:
        """The actor's carriageway leads into a junction between ``low`` and ``high`` ahead
        of it; None on a map whose carriageways lead into none."""
        into = [cw for cw in self.carriageways if cw.exit_junction is not None]
        if not into:
            return None
        terms = []
        for cw in into:
            ahead = ir.op("-", ir.const(fraction(cw.length)), s)
            terms.append((cw, ir.op("and", ir.op(">=", ahead, low), ir.op("<=", ahead, high))))
        if self.single:
            return terms[0][1]
        return ir.op("or", *(_and(self.on(road, cw), term) for cw, term in terms))

    def lanes_text(self, phase: bool = False) -> str:
        if self.single and self.uniform:
            return f"road `{self.name}` has lanes 1 to {self.most_lanes}"
        if phase:
            return f"the roads of map `{self.name}` have at most {self.most_lanes} lanes each way"
        return f"the lane is one that map `{self.name}` has where the actor starts"

    def across(
        self,
        road: ir.Var | None,
        lane: ir.Term,
        t: ir.Term,
        s: ir.Term,
        half_width: ir.Term,
        walker: bool = False,
    ) -> ir.Term:
        """The actor's sides stay on the carriageway's driving lanes (with its offset ``t``
        from the lane centre); a ``walker`` (a person, an animal) stays on the road, every
        lane of it, sidewalks and shoulders included. Lanes are taken as wide as the
        narrowest driving lane of each stretch: on maps with lanes of several widths this
        is the cautious side."""
        each: list[tuple[Carriageway, ir.Term]] = []
        for cw in self.carriageways:
            for p in cw.pieces:
                if p.count == 0:
                    continue
                width = fraction(p.width)
                right = fraction(p.right) if walker else Fraction(0)
                left = fraction(p.left) if walker else Fraction(0)
                centre = ir.op(
                    "+", ir.op("*", ir.const(width), ir.op("-", lane, ir.const(Fraction(1, 2)))), t
                )
                inside = ir.op(
                    "and",
                    ir.op(">=", centre, ir.minus(half_width, ir.const(right))),
                    ir.op("<=", centre, ir.minus(ir.const(width * p.count + left), half_width)),
                )
                each.append((cw, inside if self.uniform else _and(_within(s, p), inside)))
        return self._any(road, each)

    def beside(
        self,
        road: ir.Var | None,
        s: ir.Term,
        lane: ir.Term,
        t: ir.Term,
        other_lane: ir.Term,
        other_t: ir.Term,
        offset: ir.Term,
    ) -> ir.Term:
        """An actor in ``lane`` at ``t`` from its centre is ``offset`` to the left of one
        in ``other_lane`` at ``other_t`` on the same carriageway (lanes counted from the
        right, ``t`` to the left): the lane width times the lanes between them, plus the
        offsets, where the actor is."""
        each: list[tuple[Carriageway, ir.Term]] = []
        for cw in self.carriageways:
            for p in cw.pieces:
                if p.count == 0:
                    continue
                across = ir.op(
                    "+",
                    ir.op("*", ir.const(fraction(p.width)), ir.op("-", lane, other_lane)),
                    ir.op("-", t, other_t),
                )
                relation = ir.op("==", across, offset)
                each.append((cw, relation if self.uniform else _and(_within(s, p), relation)))
        return self._any(road, each)

    def across_text(self, actor: str, size: str, walker: bool = False) -> str:
        if walker:
            return f"`{actor}` ({size}) stays on the road (any of its lanes, sidewalks included)"
        if self.single and self.uniform:
            p = self.carriageways[0].pieces[0]
            return f"`{actor}` ({size}) stays on the road's {p.count} lanes of {p.width:g} m"
        return f"`{actor}` ({size}) stays on the driving lanes of map `{self.name}`"

    def room(self, road: ir.Var | None, reach: ir.Term, half: ir.Term) -> ir.Term:
        """``reach`` (start plus the distance driven) stays on the road ahead: the
        carriageway and what its exit leads to."""
        return self._any(
            road,
            [
                (cw, ir.op("<=", reach, _minus(cw.length + cw.ahead, half)))
                for cw in self.carriageways
            ],
        )

    def room_text(self) -> str:
        if self.single:
            return f"the {self.carriageways[0].length:g} m road `{self.name}`"
        return f"the roads of map `{self.name}`"

    def numbered(
        self, road: ir.Var | None, lane: ir.Term, s: ir.Term, number: ir.Term, from_left: bool
    ) -> ir.Term:
        """``lane`` (counted from the right) is the lane a scenario numbers ``number``."""
        if not from_left:
            return ir.op("==", lane, number)
        if self.uniform:
            top = ir.const(self.most_lanes + 1)
            return ir.op("==", lane, ir.op("-", top, number))
        return self._any(
            road,
            [
                (
                    cw,
                    _and(
                        _within(s, p), ir.op("==", lane, ir.op("-", ir.const(p.count + 1), number))
                    ),
                )
                for cw in self.carriageways
                for p in cw.pieces
                if p.count > 0
            ],
        )


def _and(a: ir.Term, b: ir.Term) -> ir.Term:
    if a == ir.TRUE:
        return b
    if b == ir.TRUE:
        return a
    return ir.op("and", a, b)


def _within(s: ir.Term, piece: LanePiece) -> ir.Term:
    return ir.op(
        "and",
        ir.op(">=", s, ir.const(fraction(piece.s0))),
        ir.op("<=", s, ir.const(fraction(piece.s1))),
    )


def between(term: ir.Term, low: int, high: int) -> ir.Term:
    return ir.op("and", ir.op(">=", term, ir.const(low)), ir.op("<=", term, ir.const(high)))


def _minus(length: float, half: ir.Term) -> ir.Term:
    return ir.minus(ir.const(fraction(length)), half)
