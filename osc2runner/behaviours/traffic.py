"""Actions of the ``traffic_light_controller``: bulb and semantic states, groups, cycles.

The lights are the scenario's ``traffic_light`` parameters
(:mod:`osc2runner.instance.lights`). Every ``set_*`` action takes effect at once
and succeeds; ``sync: true`` also sets the other lights of the light's group
(lights whose ``group.map_id`` is equal) the same way. ``play_cycles`` runs
the phases of each cycle in order, each for its ``duration``, from the cycle's
``start_offset`` into it, round and round until its phase is ended by a
``duration``, an ``until`` or its parallel's end; the phases' ``bulbs_state``
lists set the bulbs of the phase's group, matched by colour and icon.

A control file's plans (``map.set_traffic_lights_control_file``,
:mod:`osc2runner.instance.light_plans`) are played for the whole run by
:func:`run_plans`.

Every change is written to the event log (kind ``traffic_light``) with the
light's semantic state and bulbs, and noted in the light's history (the
telemetry's ``lights.csv``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

from py_trees.common import Status

from osc2runner.behaviours.base import ActionBehaviour, ActionError, InstantAction, Modifier, items
from osc2runner.compile.registry import action, method, modifier
from osc2runner.execution.context import RunContext
from osc2runner.instance.light_plans import LightPlan
from osc2runner.instance.lights import (
    SEMANTIC_BULBS,
    TrafficLight,
    as_bulbs,
    bulbs_of,
    semantic_of,
)
from osc2runner.structs import StructValue

__all__ = [
    "PlayCycles",
    "SetBulbState",
    "SetGroupBulbState",
    "SetGroupSemanticState",
    "SetGroupState",
    "SetSemanticState",
    "SetState",
    "run_plans",
    "switch",
]


#: what a switch does to a bulb: its new state, or None to leave it
BulbChange = Callable[[StructValue], str | None]


def _lights(action: ActionBehaviour) -> dict[str, TrafficLight]:
    return action.ctx.traffic_lights


def _light(action: ActionBehaviour, value: object) -> TrafficLight:
    for light in _lights(action).values():
        if light.value is value:
            return light
    raise ActionError("the `traffic_light` is not a traffic light of the scenario")


def _group(ctx: RunContext, group_id: str) -> list[TrafficLight]:
    """The scenario's lights of the group ``group_id``."""
    return [light for light in ctx.traffic_lights.values() if light.group == group_id]


def _with_sync(action: ActionBehaviour, light: TrafficLight) -> list[TrafficLight]:
    if action.args.get("sync") and light.group:
        return _group(action.ctx, light.group)
    return [light]


def switch(ctx: RunContext, lights: Iterable[TrafficLight], change: BulbChange) -> None:
    """Apply ``change(bulb) -> new state or None`` to every bulb of ``lights`` and log
    each light whose bulbs changed."""
    for light in lights:
        changed = False
        for bulb in light.bulbs:
            state = change(bulb)
            if state is not None and state != bulb.state:
                bulb.state = state
                changed = True
        if changed:
            light.changed(ctx.tick)
            ctx.record("traffic_light", light.name, light.describe())


def _semantic(state: str) -> BulbChange:
    wanted = SEMANTIC_BULBS.get(state)
    if wanted is None:
        raise ActionError(f"unknown semantic state `{state}`")
    return lambda bulb: wanted.get(str(bulb.color), "is_off")


def _bulb(color: str, icon: str, state: str) -> BulbChange:
    return lambda bulb: state if bulb.color == color and bulb.icon == icon else None


def _each(states: dict[int, str]) -> BulbChange:
    """Each bulb to its own state (``states`` by the bulb's ``id``)."""
    return lambda bulb: states[id(bulb)]


def _as_given(wanted: dict[tuple[str, str], str]) -> BulbChange:
    """Each bulb to the state ``wanted`` gives its colour and icon; off when none does."""
    return lambda bulb: wanted.get((str(bulb.color), str(bulb.icon)), "is_off")


def _by_position(action: ActionBehaviour, lights: list[TrafficLight], given: object) -> None:
    states = tuple(str(s) for s in items(given))
    for light in lights:
        if len(states) != len(light.bulbs):
            raise ActionError(
                f"`{light.name}` has {len(light.bulbs)} bulbs; {len(states)} states were given"
            )
        by_bulb = {id(b): s for b, s in zip(light.bulbs, states, strict=True)}
        switch(action.ctx, [light], _each(by_bulb))


def _group_id(value: object) -> str:
    return str(getattr(value, "map_id", ""))


def _group_lights(ctx: RunContext, group: object) -> list[TrafficLight]:
    """The scenario's lights of the ``traffic_light_group`` value ``group``; none is an error."""
    lights = _group(ctx, _group_id(group))
    if not lights:
        raise ActionError("no traffic light of the scenario is in this group")
    return lights


@action("traffic_light_controller", "set_bulb_state")
class SetBulbState(InstantAction):
    """``set_bulb_state(traffic_light, bulb_color, bulb_kind, bulb_state, sync)``: one bulb
    (of every light that has it when no light is given)."""

    def start(self) -> None:
        args = self.args
        given = args.get("traffic_light")
        lights = (
            list(_lights(self).values()) if given is None else _with_sync(self, _light(self, given))
        )
        change = _bulb(str(args["bulb_color"]), str(args["bulb_kind"]), str(args["bulb_state"]))
        switch(self.ctx, lights, change)


@action("traffic_light_controller", "set_state")
class SetState(InstantAction):
    """``set_state(traffic_light, state: list of bulb_state, sync)``: every bulb, in order."""

    def start(self) -> None:
        light = _light(self, self.args["traffic_light"])
        _by_position(self, _with_sync(self, light), self.args["state"])


@action("traffic_light_controller", "set_semantic_state")
class SetSemanticState(InstantAction):
    """``set_semantic_state(traffic_light, state, sync)``: the bulbs of that meaning."""

    def start(self) -> None:
        light = _light(self, self.args["traffic_light"])
        switch(self.ctx, _with_sync(self, light), _semantic(str(self.args["state"])))


@action("traffic_light_controller", "set_group_bulb_state")
class SetGroupBulbState(InstantAction):
    """``set_group_bulb_state(traffic_light, ...)``: one bulb of every light of the light's
    group (the standard types the parameter as a light)."""

    def start(self) -> None:
        args = self.args
        light = _light(self, args["traffic_light"])
        lights = _group(self.ctx, light.group) if light.group else [light]
        change = _bulb(str(args["bulb_color"]), str(args["bulb_kind"]), str(args["bulb_state"]))
        switch(self.ctx, lights, change)


@action("traffic_light_controller", "set_group_state")
class SetGroupState(InstantAction):
    """``set_group_state(group, state: list of bulb_state)``: every light of the group."""

    def start(self) -> None:
        _by_position(self, _group_lights(self.ctx, self.args["group"]), self.args["state"])


@action("traffic_light_controller", "set_group_semantic_state")
class SetGroupSemanticState(InstantAction):
    """``set_group_semantic_state(traffic_light_group, state)``: every light of the group."""

    def start(self) -> None:
        lights = _group_lights(self.ctx, self.args["traffic_light_group"])
        switch(self.ctx, lights, _semantic(str(self.args["state"])))


@action("traffic_light_controller", "play_cycles")
class PlayCycles(ActionBehaviour):
    """``play_cycles(cycles)``: each cycle's phases, round and round (see the module)."""

    finite = False

    def start(self) -> None:
        self.cycles = []
        for cycle in items(self.args.get("cycles")):
            phases = tuple(getattr(cycle, "phases", ()) or ())
            if not phases:
                raise ActionError("a cycle without phases cannot be played")
            period = sum(float(p.duration) for p in phases)
            if period <= 0.0:
                raise ActionError("the phases of a cycle must last longer than 0 s")
            self.cycles.append((phases, period, float(getattr(cycle, "start_offset", 0.0))))
        self.current: list[int] = [-1] * len(self.cycles)
        self._apply()

    def _apply(self) -> None:
        for n, (phases, period, offset) in enumerate(self.cycles):
            t = (self.elapsed + offset) % period
            index = 0
            while t >= float(phases[index].duration) and index < len(phases) - 1:
                t -= float(phases[index].duration)
                index += 1
            if index == self.current[n]:
                continue
            self.current[n] = index
            phase = phases[index]
            lights = _group(self.ctx, _group_id(getattr(phase, "group", None)))
            wanted = _bulb_states(getattr(phase, "bulbs_state", ()))
            switch(
                self.ctx,
                lights,
                _as_given(wanted),
            )

    def step(self) -> Status:
        self._apply()
        return Status.RUNNING


# ---------------------------------------------------------------------- control files


class _PlanPlayer:
    """Plays one controller of a control file (``instance.light_plans``): polled at the
    start of every tick, it switches the lights when a phase begins and does nothing
    in between."""

    def __init__(self, ctx: RunContext, plan: LightPlan) -> None:
        self.ctx = ctx
        self.plan = plan
        self.period = plan.period
        self.current = -1
        self.next = plan.start  # when the next phase begins (s)

    def __call__(self) -> None:
        t = self.ctx.time
        if t + 1e-9 < self.next:
            return
        plan = self.plan
        rounds = math.floor((t - plan.start + 1e-9) / self.period)
        begun = plan.start + rounds * self.period
        phases, index = plan.phases, 0
        while index < len(phases) - 1 and t + 1e-9 >= begun + phases[index].duration:
            begun += phases[index].duration
            index += 1
        phase = phases[index]
        self.next = begun + phase.duration
        if index == self.current:
            return
        self.current = index
        for light, states in phase.states:
            wanted = {id(b): state for b, state in zip(light.bulbs, states, strict=True)}
            switch(self.ctx, [light], _each(wanted))


@modifier(
    "set_traffic_lights_control_file",
    actor="map",
    note="scenario member: its plans are read before the run and played through it",
)
class SetTrafficLightsControlFile(Modifier):
    """``the_map.set_traffic_lights_control_file(file)``: the file's signal plans
    (``instance.light_plans``) run the scenario's lights from its start
    (:func:`run_plans`); nothing to do in the tree."""


def run_plans(ctx: RunContext, plans: Iterable[LightPlan]) -> None:
    """Play the control files' plans for the whole run (``instance.light_plans``): a
    controller's action switches a light at once, the plan again at its next phase."""
    for plan in plans:
        ctx.poll(_PlanPlayer(ctx, plan))


# ---------------------------------------------------------------------- methods


def _bulb_states(bulbs: object) -> dict[tuple[str, str], str]:
    """The states given bulbs ask for (a bulb given without a state: on), by colour and icon."""
    return {
        (str(b.color), str(b.icon)): str(b.fields.get("state", "is_on")) for b in as_bulbs(bulbs)
    }


@method("traffic_light", "state_equal")
def state_equal(ctx: RunContext, subject: StructValue, bulbs: object) -> bool:
    """True when the light's bulbs are in the given bulbs' states (matched by colour and
    icon; bulbs not given must be off)."""
    wanted = _bulb_states(bulbs)
    return all(
        wanted.get((str(b.color), str(b.icon)), "is_off") == str(b.state) for b in bulbs_of(subject)
    )


@method("traffic_light_group", "state_equal")
def group_state_equal(ctx: RunContext, subject: object, bulbs: object) -> bool:
    """True when every light of the group is in the given bulbs' states."""
    lights = _group(ctx, _group_id(subject))
    return bool(lights) and all(state_equal(ctx, light.value, bulbs) for light in lights)


@method("traffic_light", "semantic_state_to_state")
def semantic_state_to_state(
    ctx: RunContext, subject: StructValue, state: str
) -> tuple[StructValue, ...]:
    """The light's bulbs as the semantic state sets them (new values, the light unchanged)."""
    change = _semantic(str(state))
    return tuple(StructValue(b.struct, {**b.fields, "state": change(b)}) for b in bulbs_of(subject))


@method("traffic_light", "state_to_semantic_state")
def state_to_semantic_state(ctx: RunContext, subject: StructValue, bulbs: object) -> str:
    """The semantic state that the bulbs express (``tl.state_to_semantic_state(tl.bulbs)``)."""
    return semantic_of(as_bulbs(bulbs))
