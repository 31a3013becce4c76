"""Events the world reports: collisions between actors and leaving the road.

Collisions are checked once per control tick on the actors' bounding boxes
(oriented rectangles in the ground plane): a circle broad phase over the
candidate pairs, then a separating-axis test. Leaving the road is the world's
verdict on each moving actor's position (:class:`~osc2runner.sim.world.World`
asks the map), reported here when it changes. A pair is reported once when its boxes
start to overlap and again only after they have separated. Obstacle pairs
are never checked (they do not move), nor pairs of actors that stand still for a
while (:meth:`EventDetector.hold`: idle walkers), whose overlaps cannot change
until one of them moves again. A pair can be ignored for a while (a trailer and
its tow vehicle while hitched): its overlap is tracked but not reported, and
once it is noticed again it is reported only when its boxes start to overlap
after that.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Event", "EventDetector"]

SMALL_PAIRS = 15  # up to 6 actors: the pure-Python path


@dataclass(frozen=True, slots=True)
class Event:
    """Something that happened during a control step (``tick`` is the step's end)."""

    tick: int
    time: float
    kind: str  # "collision" or "off_road"
    actors: tuple[str, ...]
    detail: str = ""


class EventDetector:
    """Collision and road-departure detection for a fixed set of actors.

    Parameters:
        names: actor names, in the order of the pose arrays passed to :meth:`detect`.
        half_extents: half length and half width of each actor's box, shape (n, 2).
        static: which actors never move (obstacles).
        margin: boxes closer than this count as touching (m).
    """

    def __init__(
        self,
        names: Sequence[str],
        half_extents: np.ndarray,
        static: np.ndarray,
        margin: float = 0.0,
    ) -> None:
        n = len(names)
        self.names = tuple(names)
        self.half = np.asarray(half_extents, dtype=float).reshape(n, 2)
        self._half_list = [tuple(h) for h in self.half.tolist()]  # floats for the SAT test
        self.static = np.asarray(static, dtype=bool)
        self.moving = ~self.static
        self.margin = margin
        self._radius = np.hypot(self.half[:, 0], self.half[:, 1])
        self._moving_list = np.flatnonzero(self.moving).tolist()
        self._held = np.zeros(n, dtype=bool)
        self._pairs_of_held()
        self.reset()

    def _pairs_of_held(self) -> None:
        """The pairs to check (at least one actor that may move), after a change of what
        is held."""
        n = len(self.names)
        still = self.static | self._held
        pi, pj = np.triu_indices(n, k=1)
        keep = ~(still[pi] & still[pj])
        self._pi, self._pj = pi[keep], pj[keep]
        reach = self._radius[self._pi] + self._radius[self._pj] + self.margin
        self._reach2 = reach * reach
        # few actors: plain Python loops beat numpy's per-call overhead
        self._small = len(self._pi) <= SMALL_PAIRS
        self._pairs = list(
            zip(self._pi.tolist(), self._pj.tolist(), self._reach2.tolist(), strict=True)
        )
        self._still_pairs = {
            (int(a), int(b)) for a, b in zip(pi[~keep].tolist(), pj[~keep].tolist(), strict=True)
        }

    def hold(self, i: int, held: bool = True) -> None:
        """Actor ``i`` stands still from now on (``held=False``: it may move again): its
        pairs with other still actors are not checked meanwhile, once they have been
        checked with its pose at the next :meth:`detect`."""
        if held:
            if not self._held[i]:
                self._to_hold.add(i)
            return
        self._to_hold.discard(i)
        if self._held[i]:
            self._held[i] = False
            self._pairs_of_held()

    def _hold_now(self) -> None:
        for i in self._to_hold:
            self._held[i] = True
        self._to_hold.clear()
        self._pairs_of_held()

    def reset(self) -> None:
        """Forget ongoing contacts (the next overlap is reported again) and who was held."""
        self._to_hold: set[int] = set()
        if self._held.any():
            self._held[:] = False
            self._pairs_of_held()
        self._overlaps: set[tuple[int, int]] = set()
        self._off_road: set[int] = set()
        self._ignored: set[tuple[int, int]] = set()

    def ignore(self, a: int, b: int, ignored: bool = True) -> None:
        """Stop (or, with ``ignored=False``, resume) reporting the pair of actors ``a``, ``b``."""
        pair = (min(a, b), max(a, b))
        if ignored:
            self._ignored.add(pair)
        else:
            self._ignored.discard(pair)

    @property
    def collisions(self) -> frozenset[tuple[str, str]]:
        """Pairs of actors whose boxes overlap now (ignored pairs excepted)."""
        return frozenset((self.names[i], self.names[j]) for i, j in self._overlaps - self._ignored)

    def detect(
        self,
        tick: int,
        time: float,
        centre: np.ndarray,
        yaw: np.ndarray,
        off_road: Sequence[bool] = (),
    ) -> list[Event]:
        """Events at this tick, given every actor's box centre (n, 2) and yaw (n,), and for
        each moving actor (in order) whether it is off the road now."""
        events = self._leaving(tick, time, off_road)
        if self._small:
            self._detect_small(tick, time, centre.tolist(), yaw.tolist(), events)
        else:
            self._detect_many(tick, time, centre, yaw, events)
        if self._to_hold:
            self._hold_now()
        return events

    def _detect_many(
        self, tick: int, time: float, centre: np.ndarray, yaw: np.ndarray, events: list[Event]
    ) -> None:
        """:meth:`detect`'s collisions with numpy over the pairs."""
        if not len(self._pi):
            return
        diff = centre[self._pi] - centre[self._pj]
        near = np.flatnonzero(diff[:, 0] ** 2 + diff[:, 1] ** 2 <= self._reach2)
        if not near.size and not self._overlaps:
            return
        now = self._overlaps & self._still_pairs
        half = self._half_list
        for k in near.tolist():
            a, b = int(self._pi[k]), int(self._pj[k])
            if boxes_overlap(
                centre[a].tolist(),
                float(yaw[a]),
                half[a],
                centre[b].tolist(),
                float(yaw[b]),
                half[b],
                self.margin,
            ):
                now.add((a, b))
                if (a, b) not in self._overlaps and (a, b) not in self._ignored:
                    events.append(Event(tick, time, "collision", (self.names[a], self.names[b])))
        self._overlaps = now

    def _leaving(self, tick: int, time: float, off_road: Sequence[bool]) -> list[Event]:
        """``off_road`` events of the moving actors that are off the road now and were not."""
        events: list[Event] = []
        if not (self._off_road or any(off_road)):
            return events
        now_out = {i for i, off in zip(self._moving_list, off_road, strict=False) if off}
        for i in sorted(now_out - self._off_road):
            events.append(Event(tick, time, "off_road", (self.names[i],)))
        self._off_road = now_out
        return events

    def _detect_small(
        self, tick: int, time: float, centre: list[Any], yaw: list[Any], events: list[Event]
    ) -> None:
        """:meth:`detect`'s collisions for a few pairs, in plain Python (the same results)."""
        if not self._pairs:
            return
        now = self._overlaps & self._still_pairs if self._overlaps else set()
        half = self._half_list
        for a, b, reach2 in self._pairs:
            ca, cb = centre[a], centre[b]
            dx, dy = ca[0] - cb[0], ca[1] - cb[1]
            if dx * dx + dy * dy > reach2:
                continue
            if boxes_overlap(ca, yaw[a], half[a], cb, yaw[b], half[b], self.margin):
                now.add((a, b))
                if (a, b) not in self._overlaps and (a, b) not in self._ignored:
                    events.append(Event(tick, time, "collision", (self.names[a], self.names[b])))
        self._overlaps = now


def boxes_overlap(
    c1: Sequence[float],
    yaw1: float,
    h1: Sequence[float],
    c2: Sequence[float],
    yaw2: float,
    h2: Sequence[float],
    margin: float = 0.0,
) -> bool:
    """Separating-axis test of two oriented rectangles (centre, yaw, half extents)."""
    u1 = (math.cos(yaw1), math.sin(yaw1))
    v1 = (-u1[1], u1[0])
    u2 = (math.cos(yaw2), math.sin(yaw2))
    v2 = (-u2[1], u2[0])
    dx, dy = float(c2[0] - c1[0]), float(c2[1] - c1[1])
    for ax, ay in (u1, v1, u2, v2):
        r1 = h1[0] * abs(ax * u1[0] + ay * u1[1]) + h1[1] * abs(ax * v1[0] + ay * v1[1])
        r2 = h2[0] * abs(ax * u2[0] + ay * u2[1]) + h2[1] * abs(ax * v2[0] + ay * v2[1])
        if abs(dx * ax + dy * ay) > r1 + r2 + margin:
            return False
    return True
