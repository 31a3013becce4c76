"""The ScenarioInitializer: every actor's pose and speed before the first tick.

The phases that start the scenario (the first member of each ``serial``,
every member of a ``parallel`` or ``one_of``, and what follows instantaneous
actions such as ``assign_position``) carry the start constraints:

* modifiers with ``at: start``: ``lane``, ``position``, ``lateral``,
  ``speed``, ``yaw``/``orientation``;
* position-like modifiers of those phases that hold throughout (``lane``,
  ``position``, ``lateral`` with ``at: all``) fill in what ``at: start``
  leaves open — a speed that holds throughout is reached by the controller,
  not assumed at the start;
* ``assign_speed`` and friends.

Each modifier contributes through its ``place`` hook to a :class:`StartPlan`,
which resolves relative placements (``position(distance: 5m, behind: hero)``,
``lane(side: right, side_of: hero)``) in dependency order. Actors without a
longitudinal position are laid out from :data:`START_MARGIN` so that nothing
starts off the road or overlapping; obstacles nobody placed stand at the far
end of the road. A placement that cannot be realised (a lane the road does not
have, a cycle of relative positions) is an input error with its location.

When the solver's witness lands it will supply start poses directly; this
module stays the fallback and the place where poses become
:class:`~osc2runner.sim.ActorSpec` s.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from osc2check.syntax import ast
from osc2runner.actors import Actor
from osc2runner.errors import Problem, problem
from osc2runner.roads import LaneNumbers
from osc2runner.sim import ActorSpec

__all__ = ["START_MARGIN", "StartPlan", "StartPose"]

#: the rearmost actor's rear end starts this far from the road's entry (m)
START_MARGIN = 30.0
#: free space kept between actors laid out in the same lane (m)
LAYOUT_GAP = 5.0


@dataclass
class _Rel:
    ref: str
    delta: float
    node: ast.Node | None


@dataclass
class StartPose:
    """What the start constraints say about one actor."""

    lane: int | _Rel | None = None  # a road lane, or lanes to the left of a reference
    s: float | _Rel | None = None  # along the road, or metres ahead of a reference
    offset: float | None = None  # to the left of the lane centre (m)
    yaw: float | None = None  # relative to the road heading (rad)
    speed: float | None = None
    nodes: dict[str, ast.Node | None] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class Placement:
    """A resolved start: road coordinates, yaw and speed."""

    s: float
    lane: int
    offset: float
    yaw: float
    speed: float


class StartPlan:
    """Collects start constraints per actor and resolves them (see the module docs)."""

    def __init__(self, actors: list[Actor], lanes: LaneNumbers) -> None:
        self.actors = {a.name: a for a in actors}
        self.order = [a.name for a in actors]
        self.lanes = lanes
        self.road = lanes.road
        self.poses: dict[str, StartPose] = {a.name: StartPose() for a in actors}
        self.problems: list[Problem] = []
        self.notes: list[str] = []

    # ---- constraints (called by modifiers' place hooks)

    def _set(
        self, actor: str, key: str, value: Any, node: ast.Node | None, weak: bool = False
    ) -> None:
        pose = self.poses[actor]
        if getattr(pose, key) is not None:
            if weak:
                return
            if getattr(pose, key) != value:
                self.notes.append(f"`{actor}`: a later start constraint on its {key} wins")
        setattr(pose, key, value)
        pose.nodes[key] = node

    def lane(self, actor: str, lane: int, node: ast.Node | None, weak: bool = False) -> None:
        """Start in road lane ``lane`` (1 = rightmost)."""
        self._set(actor, "lane", int(lane), node, weak)

    def lane_beside(
        self, actor: str, ref: str, lanes_left: int, node: ast.Node | None, weak: bool = False
    ) -> None:
        """Start ``lanes_left`` lanes to the left of ``ref``'s start lane (negative: right)."""
        self._set(actor, "lane", _Rel(ref, lanes_left, node), node, weak)

    def s(self, actor: str, s: float, node: ast.Node | None, weak: bool = False) -> None:
        self._set(actor, "s", float(s), node, weak)

    def s_from(
        self, actor: str, ref: str, ahead: float, node: ast.Node | None, weak: bool = False
    ) -> None:
        """Start ``ahead`` metres ahead of ``ref`` along the road (reference points)."""
        self._set(actor, "s", _Rel(ref, float(ahead), node), node, weak)

    def offset(self, actor: str, offset: float, node: ast.Node | None, weak: bool = False) -> None:
        self._set(actor, "offset", float(offset), node, weak)

    def yaw(self, actor: str, yaw: float, node: ast.Node | None) -> None:
        self._set(actor, "yaw", float(yaw), node)

    def speed(self, actor: str, speed: float, node: ast.Node | None) -> None:
        self._set(actor, "speed", float(speed), node)

    # ---- resolution

    def resolve(self) -> dict[str, Placement]:
        """Every body actor's start; problems are collected in ``self.problems``."""
        bodies = [n for n in self.order if self.actors[n].has_body]
        lanes = self._resolve_lanes(bodies)
        s = self._resolve_s(bodies, lanes)
        result: dict[str, Placement] = {}
        for name in bodies:
            pose = self.poses[name]
            lane = lanes.get(name)
            if lane is None or name not in s:
                continue
            result[name] = Placement(
                s=s[name],
                lane=lane,
                offset=pose.offset or 0.0,
                yaw=self.road.heading + (pose.yaw or 0.0),
                speed=pose.speed or 0.0,
            )
        return result

    def _chain(self, name: str, key: str) -> list[str]:
        """``name`` and the references its ``key`` depends on, nearest first."""
        chain = [name]
        value = getattr(self.poses[name], key)
        while isinstance(value, _Rel):
            if value.ref in chain:
                cycle = " -> ".join([*chain, value.ref])
                self.problems.append(
                    problem(
                        f"start positions depend on each other in a cycle ({cycle})", value.node
                    )
                )
                return []
            if value.ref not in self.poses:
                self.problems.append(
                    problem(f"`{value.ref}` is not an actor of this scenario", value.node)
                )
                return []
            chain.append(value.ref)
            value = getattr(self.poses[value.ref], key)
        return chain

    def _resolve_lanes(self, bodies: list[str]) -> dict[str, int]:
        lanes: dict[str, int] = {}
        default = self.lanes.to_road(1)
        for name in bodies:
            chain = self._chain(name, "lane")
            if not chain:
                continue
            root = self.poses[chain[-1]].lane
            lane = root if isinstance(root, int) else None
            if lane is None:
                # no lane: the lane of the actor its position refers to, else the first lane
                anchor = self.poses[chain[-1]].s
                if isinstance(anchor, _Rel) and isinstance(self.poses[anchor.ref].lane, int):
                    lane = self.poses[anchor.ref].lane  # type: ignore[assignment]
                else:
                    lane = default
            for link in reversed(chain[:-1]):
                rel = self.poses[link].lane
                assert isinstance(rel, _Rel)
                lane = lane + int(rel.delta)
                if not self.road.has_lane(lane):
                    self.problems.append(
                        problem(
                            f"`{link}` would start in a lane the road does not have: "
                            f"{self._lane_text(lane)}",
                            rel.node,
                        )
                    )
                    break
            else:
                if not self.road.has_lane(lane):
                    self.problems.append(
                        problem(
                            f"`{name}` would start in a lane the road does not have: "
                            f"{self._lane_text(lane)}",
                            self.poses[name].nodes.get("lane"),
                        )
                    )
                    continue
                lanes[name] = lane
        return lanes

    def _lane_text(self, lane: int) -> str:
        road = self.road
        side = self.lanes.default_side
        return (
            f"map `{road.name}` has lanes 1..{road.lane_count}, counted from the {side}; "
            f"this is lane {self.lanes.to_scenario(lane)}"
        )

    def _length(self, name: str) -> float:
        params = self.actors[name].params
        return float(getattr(params, "length", 1.0))

    def _resolve_s(self, bodies: list[str], lanes: dict[str, int]) -> dict[str, float]:
        # relative offsets from each actor to the root of its chain
        groups: dict[str, dict[str, float]] = {}
        absolute: dict[str, float] = {}
        for name in bodies:
            chain = self._chain(name, "s")
            if not chain:
                continue
            offset = 0.0
            for link in chain[:-1]:
                rel = self.poses[link].s
                assert isinstance(rel, _Rel)
                offset += rel.delta
            root = chain[-1]
            root_s = self.poses[root].s
            if isinstance(root_s, float):
                absolute[name] = root_s + offset
            else:
                groups.setdefault(root, {})[name] = offset
        placed: dict[str, float] = dict(absolute)
        free_obstacles = []
        for root in self.order:
            group = groups.get(root)
            if not group:
                continue
            if (
                set(group) == {root}
                and self.actors[root].kind == "obstacle"
                and self.poses[root].lane is None
            ):
                free_obstacles.append(root)
                continue
            base = max(START_MARGIN + 0.5 * self._length(n) - off for n, off in group.items())
            base = self._clear(base, group, lanes, placed)
            for n, off in group.items():
                placed[n] = base + off
        for i, name in enumerate(free_obstacles):
            placed[name] = self.road.length - 20.0 - 15.0 * i
            self.notes.append(f"`{name}` has no start position: placed at the end of the road")
        for name, s in placed.items():
            half = 0.5 * self._length(name)
            if s - half < 0.0 or s + half > self.road.length:
                self.problems.append(
                    problem(
                        f"`{name}` would start off the road (s = {s:.1f} m on a road of "
                        f"{self.road.length:.0f} m)",
                        self.poses[name].nodes.get("s"),
                    )
                )
        return placed

    def _clear(
        self, base: float, group: dict[str, float], lanes: dict[str, int], placed: dict[str, float]
    ) -> float:
        """The smallest ``base`` >= the given one at which the group overlaps nobody placed."""
        for _ in range(100):
            shift = 0.0
            for n, off in group.items():
                for other, s_other in placed.items():
                    if lanes.get(n) != lanes.get(other):
                        continue
                    need = 0.5 * (self._length(n) + self._length(other)) + LAYOUT_GAP
                    s = base + off
                    if abs(s - s_other) < need:
                        shift = max(shift, s_other + need - s)
            if shift <= 0.0:
                return base
            base += shift
        return base

    # ---- world specs

    def specs(self, placements: dict[str, Placement]) -> list[ActorSpec]:
        """World actor specs in declaration order."""
        specs = []
        for name in self.order:
            actor = self.actors[name]
            if not actor.has_body or name not in placements:
                continue
            p = placements[name]
            specs.append(
                ActorSpec(
                    name,
                    actor.params,
                    s=p.s,
                    lane=p.lane,
                    offset=p.offset,
                    yaw=p.yaw,
                    speed=p.speed,
                )
            )
        return specs
