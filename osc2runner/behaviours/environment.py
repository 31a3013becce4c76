"""Environment actions: weather and road friction. Each takes effect at once and succeeds.

Rain sets the road friction (1.0 dry, 0.7 light to 0.4 heavy rain) unless a
friction was set explicitly; ``set_road_friction`` sets it for the whole road.
Fog is recorded (it has no effect on vehicle dynamics). Air, snow, wind and
clouds are recorded in ``env.weather`` and the event log; the sun's and the
moon's positions in the sky (``sim.sky``: ``env.sun.position``).

A friction outside :data:`FRICTION_RANGE` (0, 2], or a rain intensity that is
negative or not finite, is an input error at its argument when the argument
is constant (a literal, a parameter); otherwise the phase fails when the value
turns out bad at run time. The ranges are ``osc2check.world.limits``'s, which
the checker verifies too.
"""

from __future__ import annotations

from collections.abc import Callable

from osc2check.syntax import ast
from osc2check.world.limits import FRICTION_RANGE, friction_problem, mps_to_mmph, rain_problem
from osc2runner.behaviours.base import ActionError, ActionUse, InstantAction, number
from osc2runner.compile.expressions import is_constant
from osc2runner.compile.registry import action
from osc2runner.errors import CompileProblem
from osc2runner.sim.sky import LightSource

__all__ = ["FRICTION_RANGE", "Fog", "Rain", "Recorded", "SetRoadFriction", "friction_problem"]

#: rain intensity (mm/h) taken as the heaviest rain of the friction model
HEAVY_RAIN_MMPH = 50.0
#: visual range (m) below which it is foggy at all
FOG_RANGE = 1000.0
_RECORDED = "recorded, readable in env.weather; no effect on dynamics"


def _check_constant(use: ActionUse, name: str, problem: Callable[[object], str | None]) -> None:
    """Raise CompileProblem (an input error at the argument) when the argument ``name`` is
    constant and ``problem`` finds it bad."""
    fn = use.arguments.get(name)
    if fn is None or not is_constant(fn):
        return
    why = problem(fn())
    if why is not None:
        raise CompileProblem(why, _argument(use, name))


def _argument(use: ActionUse, name: str) -> ast.Node:
    """The expression given for the parameter ``name`` (the invocation when not found)."""
    return use.given(name) or use.node


def update_weather(action: InstantAction, part: str) -> None:
    """Write the action's arguments into ``env.weather.<part>`` (what expressions read);
    parameters not given leave that part unchanged."""
    target = getattr(action.ctx.weather, part)
    for key, value in action.args.items():
        if hasattr(target, key):
            setattr(target, key, value)


@action("environment", "rain")
class Rain(InstantAction):
    """``rain(intensity)``: rain level = intensity / 50 mm/h (capped at 1)."""

    def __init__(self, name: str, use: ActionUse) -> None:
        super().__init__(name, use)
        _check_constant(use, "intensity", rain_problem)

    def start(self) -> None:
        if "intensity" not in self.args:
            return
        why = rain_problem(self.args["intensity"])
        if why is not None:
            raise ActionError(why)
        update_weather(self, "rain")
        mmph = mps_to_mmph(number(self.args["intensity"]))
        level = min(max(mmph / HEAVY_RAIN_MMPH, 0.0), 1.0)
        world = self.ctx.attached_world
        world.set_weather(rain=level)
        self.ctx.environment_changed(
            "rain",
            self.args,
            f"{mmph:.6g} mm/h -> level {level:.3g}, road friction {world.road_friction:.3g}",
        )


@action("environment", "fog", note=_RECORDED)
class Fog(InstantAction):
    """``fog(visual_range)``: fog level = 1 - range / 1000 m (recorded)."""

    def start(self) -> None:
        if "visual_range" not in self.args:
            return
        update_weather(self, "fog")
        visual = number(self.args["visual_range"])
        level = min(max(1.0 - visual / FOG_RANGE, 0.0), 1.0)
        self.ctx.attached_world.set_weather(fog=level)
        detail = f"visual range {visual:.6g} m -> level {level:.3g}"
        self.ctx.environment_changed("fog", self.args, detail)


@action("environment", "set_road_friction")
class SetRoadFriction(InstantAction):
    """``set_road_friction(value)``: the tire-road friction of the whole road from now on."""

    def __init__(self, name: str, use: ActionUse) -> None:
        super().__init__(name, use)
        _check_constant(use, "value", friction_problem)

    def start(self) -> None:
        why = friction_problem(self.args["value"])
        if why is not None:
            raise ActionError(why)
        value = number(self.args["value"])
        self.ctx.attached_world.set_road_friction(value)
        self.ctx.environment_changed("set_road_friction", self.args, f"{value:.6g}")


class Recorded(InstantAction):
    """An environment action with no physical effect here: its arguments go to the event log."""

    part: str | None = None  # the part of ``env.weather`` it sets

    def start(self) -> None:
        if self.part is not None:
            update_weather(self, self.part)
        detail = ", ".join(
            f"{k}: {v:.6g}" if isinstance(v, float) else f"{k}: {v}" for k, v in self.args.items()
        )
        self.ctx.environment_changed(self.use.symbol.name, self.args, detail)


@action("environment", "air", note=_RECORDED)
class RecordedAir(Recorded):
    """``air``: recorded in the event log only."""

    part = "air"


@action("environment", "snow", note=_RECORDED)
class RecordedSnow(Recorded):
    """``snow``: recorded in the event log only."""

    part = "snow"


@action("environment", "wind", note=_RECORDED)
class RecordedWind(Recorded):
    """``wind``: recorded in the event log only."""

    part = "wind"


@action("environment", "clouds", note=_RECORDED)
class RecordedClouds(Recorded):
    """``clouds``: recorded in the event log only."""

    part = "clouds"


@action("environment", "assign_celestial_position", note="readable in env.sun, env.moon")
class AssignCelestialPosition(Recorded):
    """``assign_celestial_position(light_source, azimuth, elevation)``: the sun or the moon
    is there at once (``sim.sky``); an angle not given keeps its value; without a
    ``light_source`` (mandatory in the standard), the sun."""

    def start(self) -> None:
        source = self.args.get("light_source", LightSource("sun", self.ctx.sky))
        if not isinstance(source, LightSource):
            raise ActionError("`light_source` is not the environment's sun or moon")
        azimuth, elevation = self.args.get("azimuth"), self.args.get("elevation")
        source.sky.assign(
            source.name,
            None if azimuth is None else number(azimuth),
            None if elevation is None else number(elevation),
        )
        super().start()
