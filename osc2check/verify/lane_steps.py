"""The lane an actor is in as its phases follow one another, for lane changes (L503).

ASAM OpenSCENARIO DSL 2.1 §8.8 ``change_lane(num_of_lanes, side)`` and §8.9 the
``change_lane(lane, side)`` modifier move an actor that many lanes to a side of the
lane it is in when the phase starts; there must be such a lane. Placement knows
each actor's start lane (a solver variable) and the lane of every later phase that
``lane(k)`` gives (one more variable each); this module follows each actor through
its invocations in the order they run and says, for every lane change, which lane it
ends in as a term over those variables, so that placement requires a lane the road
has there (the rule ``lane-range``, L503) before anything runs.

The lane is followed through the actor's invocations in source order, which is the
order they run in (``serial``; an actor moving in two ``parallel`` branches at once
is B-code's to report). It is no longer known after anything that moves the actor
sideways in another way: a change without a constant ``side`` (the runner draws
one), one relative to a reference or to a target lane, ``lane`` relative to another
actor, a path, a position, an invocation inside a ``one_of`` (which member runs is
the seed's). Sides: ``left``, ``inside`` (towards opposing traffic, under right-hand
traffic) add to the lane number (lanes are counted from the right), ``right`` and
``outside`` subtract, ``same`` keeps it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from osc2check.semantics.model import Model
from osc2check.semantics.phases import enum_word, modifier_timing, tree_members
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir

__all__ = ["LaneChange", "LaneSteps", "one_of_members"]

#: actions and modifiers after which an actor's lane is not known any more
_MOVES_SIDEWAYS = frozenset(
    {
        "assign_position", "change_position", "follow_path", "replay_path",
        "follow_trajectory", "replay_trajectory", "along", "along_trajectory", "lateral",
        "follow_lane",
    }
)  # fmt: skip
_SIDES = {"left": 1, "inside": 1, "right": -1, "outside": -1, "same": 0}


@dataclass(frozen=True)
class LaneChange:
    """A lane change of ``actor`` by ``inv``: the term of the lane it ends in (counted from
    the right) and how it reads."""

    actor: str
    inv: ast.Invocation
    lane: ir.Term
    text: str


def one_of_members(bodies: Iterable[ast.Node]) -> set[int]:
    """The ids of the invocations inside a ``one_of`` of ``bodies`` (declarations)."""
    found: set[int] = set()
    for body in bodies:
        for member in getattr(body, "members", ()):  # compositions are only in `do` trees
            if not isinstance(member, ast.DoDirective):
                continue
            for node in tree_members(member):
                if isinstance(node, ast.Composition) and node.op == "one_of":
                    found.update(id(n) for n in walk(node) if isinstance(n, ast.Invocation))
    return found


@dataclass
class LaneSteps:
    """Each actor's lane term as its invocations run (see the module docstring).

    ``value`` folds an argument to an integer term (None when it cannot). Lanes are
    counted from the right; ``left_is_inside`` is False on a map of left-hand traffic.
    """

    model: Model
    value: Callable[[ast.Node], ir.Term | None]
    uncertain: set[int]
    left_is_inside: bool = True
    lanes: dict[str, ir.Term | None] = field(default_factory=dict)

    def run(
        self,
        actor: str,
        start: ir.Var,
        inv: ast.Invocation,
        phase_lane: Callable[[ast.Invocation], ir.Var | None],
    ) -> list[LaneChange]:
        """The lane changes of ``actor``'s invocation ``inv`` (the next it runs);
        ``phase_lane`` is the variable of the lane a later phase's ``lane(k)`` gives
        (``start`` itself for a modifier applied at the start; None when there is none)."""
        lane = self.lanes.get(actor, ir.Ref(start))
        if id(inv) in self.uncertain:
            self.lanes[actor] = None
            return []
        changes: list[LaneChange] = []
        ends: ir.Term | None = None
        for item in inv.with_members:
            if not isinstance(item, ast.Invocation):
                continue
            args = self._args(item)
            name = item.name.text
            if name == "lane":
                given = self._absolute(item, args, start, phase_lane)
                if modifier_timing(args) == "end":
                    ends = given
                else:
                    lane = given
            elif name in _MOVES_SIDEWAYS:
                lane = None
        if inv.name.text == "change_lane" and inv.actor is not None:
            lane = self._change(actor, inv, self._args(inv), "num_of_lanes", lane, changes)
        elif inv.name.text in _MOVES_SIDEWAYS:
            lane = None
        for item in inv.with_members:
            if isinstance(item, ast.Invocation) and item.name.text == "change_lane":
                lane = self._change(actor, item, self._args(item), "lane", lane, changes)
        self.lanes[actor] = ends if ends is not None else lane
        return changes

    def _args(self, call: ast.Invocation, defaults: bool = True) -> dict[str, ast.Node]:
        binding = self.model.binding(call)
        return dict(binding.values(defaults=defaults)) if binding is not None else {}

    @staticmethod
    def _absolute(
        item: ast.Invocation,
        args: dict[str, ast.Node],
        start: ir.Var,
        phase_lane: Callable[[ast.Invocation], ir.Var | None],
    ) -> ir.Term | None:
        """The lane a ``lane(k)`` modifier puts the actor in, or None (relative, a range,
        in a later phase). One applied at the start puts it in the start lane, whatever
        it is relative to: placement solves that lane."""
        var = phase_lane(item)
        if var is start:
            return ir.Ref(start)
        if any(k in args for k in ("same_as", "side_of", "left_of", "right_of")):
            return None
        if "lane" not in args or isinstance(args["lane"], ast.RangeLiteral):
            return None
        return ir.Ref(var if var is not None else start)

    def _change(
        self,
        actor: str,
        call: ast.Invocation,
        args: dict[str, ast.Node],
        count_name: str,
        lane: ir.Term | None,
        changes: list[LaneChange],
    ) -> ir.Term | None:
        """The lane after the change ``call`` (None when it is not known)."""
        written = self._args(call, defaults=False)
        if lane is None or any(k in written for k in ("reference", "target")):
            return None
        side = enum_word(args.get("side"))
        sign = _SIDES.get(side or "")
        if sign is None:
            return None
        if side in ("inside", "outside") and not self.left_is_inside:
            sign = -sign
        count = self.value(args[count_name]) if count_name in args else ir.const(1)
        if count is None:
            return None
        if sign == 0:
            return lane
        moved = ir.op("+", lane, count if sign > 0 else ir.op("neg", count))
        changes.append(
            LaneChange(
                actor,
                call,
                moved,
                f"`{actor}` changes lanes to the {side} of the lane it is in, to a lane the "
                "road has",
            )
        )
        return moved
