"""``set_lights(mode)`` (toolkit): the vehicle's light mode, recorded at once."""

from __future__ import annotations

from osc2runner.behaviours.base import ActionError, InstantAction
from osc2runner.compile.registry import action

__all__ = ["SetLights", "LIGHT_MODES"]

LIGHT_MODES = ("high_beam", "low_beam", "auto", "off")


@action("vehicle", "set_lights")
class SetLights(InstantAction):
    """Switch the lights: ``high_beam``, ``low_beam``, ``auto`` or ``off`` (event log)."""

    def start(self) -> None:
        mode = str(self.args.get("mode", ""))
        if mode not in LIGHT_MODES:
            raise ActionError(f"unknown light mode `{mode}`; known: {', '.join(LIGHT_MODES)}")
        self.ctx.lights[self.actor.name] = mode
        self.ctx.record("lights", self.actor.name, mode, actors=(self.actor.name,))
