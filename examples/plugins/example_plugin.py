"""An example plug-in (docs/plugins.md): implementations of behaviours that .osc
libraries declare.

* ``log(msg)``: scenario_execution's action (its library ``osc.helpers``:
  ``action log: msg: string``), an instant action that writes a line of the event
  log;
* ``vehicle.accelerate_to(target, rate)``: a driving action of ``driving.osc``
  beside this file, lasting until the vehicle drives at ``target``.

    osc2run examples/plugins/greeting.osc --plugin examples/plugins/example_plugin.py
"""

from __future__ import annotations

from osc2check.plugins import action


@action("log")
def log(run, msg):
    """Write ``msg`` into the event log."""
    run.log(msg)


@action("accelerate_to", actor="vehicle")
class AccelerateTo:
    """Change speed to ``target`` at no more than ``rate``; done within 0.1 m/s of it."""

    def start(self, run, actor, target, rate):
        self.target = target
        run.set_speed(actor, target, acceleration=rate)
        run.log(f"{actor.name} accelerates to {target * 3.6:.0f} kph")

    def step(self, run, actor):
        return abs(actor.speed - self.target) < 0.1
