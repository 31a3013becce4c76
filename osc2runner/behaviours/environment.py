"""Environment actions: weather and road friction. Each takes effect at once and succeeds.

Rain sets the road friction (1.0 dry, 0.7 light to 0.4 heavy rain) unless a
friction was set explicitly; ``set_road_friction`` sets it for the whole road.
Fog is recorded (it has no effect on vehicle dynamics). Air, snow, wind,
clouds and the sun's position are recorded in the event log only.
"""

from __future__ import annotations

from osc2runner.behaviours.base import ActionError, InstantAction
from osc2runner.compile.registry import action

__all__ = ["Fog", "Rain", "Recorded", "SetRoadFriction"]

#: rain intensity (mm/h) taken as the heaviest rain of the friction model
HEAVY_RAIN_MMPH = 50.0
#: visual range (m) below which it is foggy at all
FOG_RANGE = 1000.0
_MPS_TO_MMPH = 3.6e6


@action("environment", "rain")
class Rain(InstantAction):
    """``rain(intensity)``: rain level = intensity / 50 mm/h (capped at 1)."""

    def start(self) -> None:
        if "intensity" not in self.args:
            return
        mmph = float(self.args["intensity"]) * _MPS_TO_MMPH
        level = min(max(mmph / HEAVY_RAIN_MMPH, 0.0), 1.0)
        world = self.ctx.world
        world.set_weather(rain=level)
        self.ctx.record(
            "environment",
            "rain",
            f"{mmph:.6g} mm/h -> level {level:.3g}, road friction {world.road_friction:.3g}",
        )


@action("environment", "fog", note="recorded; no effect on dynamics")
class Fog(InstantAction):
    """``fog(visual_range)``: fog level = 1 - range / 1000 m (recorded)."""

    def start(self) -> None:
        if "visual_range" not in self.args:
            return
        visual = float(self.args["visual_range"])
        level = min(max(1.0 - visual / FOG_RANGE, 0.0), 1.0)
        self.ctx.world.set_weather(fog=level)
        self.ctx.record("environment", "fog", f"visual range {visual:.6g} m -> level {level:.3g}")


@action("environment", "set_road_friction")
class SetRoadFriction(InstantAction):
    """``set_road_friction(value)``: the tire-road friction of the whole road from now on."""

    def start(self) -> None:
        value = float(self.args["value"])
        if value <= 0.0:
            raise ActionError(f"road friction must be positive, got {value}")
        self.ctx.world.set_road_friction(value)
        self.ctx.record("environment", "set_road_friction", f"{value:.6g}")


class Recorded(InstantAction):
    """An environment action with no physical effect here: its arguments go to the event log."""

    def start(self) -> None:
        detail = ", ".join(
            f"{k}: {v:.6g}" if isinstance(v, float) else f"{k}: {v}" for k, v in self.args.items()
        )
        self.ctx.record("environment", self.use.symbol.name, detail)


_RECORDED = "recorded; no effect on dynamics"


@action("environment", "air", note=_RECORDED)
class RecordedAir(Recorded):
    """``air``: recorded in the event log only."""


@action("environment", "snow", note=_RECORDED)
class RecordedSnow(Recorded):
    """``snow``: recorded in the event log only."""


@action("environment", "wind", note=_RECORDED)
class RecordedWind(Recorded):
    """``wind``: recorded in the event log only."""


@action("environment", "clouds", note=_RECORDED)
class RecordedClouds(Recorded):
    """``clouds``: recorded in the event log only."""


@action("environment", "assign_celestial_position", note=_RECORDED)
class RecordedCelestialPosition(Recorded):
    """``assign_celestial_position``: recorded in the event log only."""
