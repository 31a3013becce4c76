"""``connect_trailer`` and ``disconnect_trailer``: a vehicle hitches and unhitches a trailer.

The trailer is a body of its own (``sim/trailer.py``); hitching joins its coupler to
the tow vehicle's receiver with a ball joint, so that the tow vehicle pulls,
brakes and steers it through the physics. Both actions are instant.

* ``tow.connect_trailer(trailer: t)``: ``t`` is hitched to ``tow``. A trailer
  whose coupler is not on the receiver is first put there, aligned behind the
  tow vehicle at its speed (**choice**: the standard says nothing of where the
  trailer is; a trailer the checker placed on the hitch, as it does for a
  ``connect_trailer`` that begins at time 0, is not moved); how far it moved is
  in the event log. It fails when the vehicle has no hitch receiver (a
  two-wheeler), already tows a trailer, or the trailer is towed by another.
* ``tow.disconnect_trailer()``: the trailer is unhitched where it is; its own
  brakes hold it (a braked trailer's breakaway/parking brake) or it rolls out
  on its wheels and its front support (an unbraked one). It fails when the
  vehicle tows nothing.

The tow vehicle's speed controller is told of the load (its inverse model adds
the trailer's mass and resistance); the physics does the rest. Every change is
in the event log (kind ``trailer``).
"""

from __future__ import annotations

from collections.abc import Iterable

from osc2runner.behaviours.base import ActionError, ActionUse, InstantAction
from osc2runner.compile.registry import action
from osc2runner.execution.controls import Controller
from osc2runner.instance.actors import Actor
from osc2runner.sim.controllers import SpeedController
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import VehicleParams

__all__ = ["ConnectTrailer", "DisconnectTrailer", "hitches_at_start"]


def _trailer_argument(value: object) -> Actor:
    if not isinstance(value, Actor):
        raise ActionError("`trailer` must be a trailer actor of the scenario")
    if value.kind != "trailer":
        raise ActionError(f"`{value.name}` is not a trailer")
    return value


def hitches_at_start(start_uses: Iterable[ActionUse]) -> dict[str, str]:
    """The trailers that ``connect_trailer`` invocations beginning at time 0 hitch, and
    their tow vehicles (``trailer -> tow``): the world starts with them hitched."""
    found: dict[str, str] = {}
    for use in start_uses:
        if use.behaviour is not ConnectTrailer or "trailer" not in use.arguments:
            continue
        trailer = use.arguments["trailer"]()
        tow = use.actor
        can_tow = isinstance(tow.params, VehicleParams) and tow.params.can_tow
        if not (isinstance(trailer, Actor) and trailer.kind == "trailer" and can_tow):
            continue  # the action fails when it starts, saying why
        if trailer.name not in found and tow.name not in found.values():
            found[trailer.name] = tow.name
    return found


_BUILT = "central-axle trailers (semi- and full trailers are not built)"


@action("vehicle", "connect_trailer", note=f"a ball joint at the hitch; {_BUILT}")
class ConnectTrailer(InstantAction):
    """Hitch the trailer to the vehicle's receiver (see the module docstring)."""

    def start(self) -> None:
        trailer = _trailer_argument(self.args.get("trailer"))
        world = self.ctx.attached_world
        tow = self.actor.name
        if world.hitched.get(trailer.name) == tow:
            moved = 0.0  # hitched from the start, where the checker placed it
        else:
            try:
                moved = world.connect(tow, trailer.name)
            except ValueError as exc:
                raise ActionError(str(exc)) from None
            self.ctx.refresh()
        tow_load(self.controller, world.params(trailer.name))
        self.ctx.record(
            "trailer",
            f"{tow}-{trailer.name}",
            f"connected (trailer moved {moved:.2f} m)",
            actors=(tow, trailer.name),
        )


@action("vehicle", "disconnect_trailer", note="the trailer's own brakes hold it, if it has any")
class DisconnectTrailer(InstantAction):
    """Unhitch the trailer the vehicle tows (see the module docstring)."""

    def start(self) -> None:
        world = self.ctx.attached_world
        tow = self.actor.name
        try:
            trailer = world.disconnect(tow)
        except ValueError as exc:
            raise ActionError(str(exc)) from None
        tow_load(self.controller, None)
        self.ctx.record("trailer", f"{tow}-{trailer}", "disconnected", actors=(tow, trailer))


def tow_load(controller: Controller | None, params: object) -> None:
    """Tell a vehicle's speed controller of the trailer it tows now (None: none)."""
    speed = controller.speed if controller is not None else None
    if isinstance(speed, SpeedController):
        speed.towed = params if isinstance(params, TrailerParams) else None
