"""An autonomous emergency braking (AEB) function: the example system under test.

It drives as the scenario asks (it passes the driver model's pedals and
steering through) until an actor in its path comes close in time, then brakes
on its own, as a simple production AEB does:

* time to collision ``TTC = gap / closing speed`` to the actors ahead that it
  closes in on and that overlap the car's width, now or when the car reaches
  them at their lateral speed (a pedestrian walking into its path);
* below ``ttc_partial`` (1.4 s) it brakes with ``partial_decel`` (4 m/s²);
* below ``ttc_full`` (0.8 s), or when stopping needs more than ``partial_decel``
  (the closing speed squared over twice the gap), it brakes fully;
* once braking it holds the brake until it no longer closes in (or stands
  still), then hands back to the driver.

It sees the world after ``latency`` (0.2 s: sensing and decision), so it
acts on what it saw four ticks before (at the default 20 Hz), and its brake
builds up at the vehicle's pedal rate. Stopping from speed ``v`` at full braking (about
9 m/s² on dry asphalt) takes ``v² / 18`` metres, so it avoids stationary
targets up to about 40 kph and only reduces the impact speed above.

    osc2run examples/ncap/ccrs.osc --seed 3 --sut examples/controllers/aeb.py:Aeb
"""

from __future__ import annotations

from osc2runner.sut import Command, Demand, Observation, SutInfo


class Aeb:
    """Time-to-collision braking on top of the scenario's driver (see the module docstring)."""

    ttc_partial = 1.4  # s
    ttc_full = 0.8  # s
    partial_decel = 4.0  # m/s²
    escalate = 2.0  # full braking once stopping needs this many times partial_decel
    latency = 0.2  # s from sensing to braking

    def reset(self, info: SutInfo) -> None:
        self.info = info
        self.braking = False
        self.delay = max(0, round(self.latency / info.dt))
        self.pending: list[bool | str] = []  # decisions not yet acted on (latency)
        self.interventions = 0

    def threats(self, obs: Observation) -> list[tuple[float, float]]:
        """``(TTC, closing speed)`` of every actor ahead the car will hit if nothing changes."""
        found = []
        for o in obs.others:
            if o.rel_x <= 0.0 or o.rel_vx >= 0.0:
                continue
            closing = -o.rel_vx
            ttc = max(o.gap, 0.0) / closing
            half_widths = abs(o.rel_y) - o.lateral_gap  # the two half widths, side by side
            if abs(o.rel_y + o.rel_vy * ttc) < half_widths:  # in the path when reached
                found.append((ttc, closing))
        return found

    def decide(self, obs: Observation) -> bool | str:
        """False (no braking), "partial" or "full", from what is seen now."""
        threats = self.threats(obs)
        if not threats:
            return False
        ttc, closing = min(threats)
        gap = max(ttc * closing, 0.01)
        needed = closing * closing / (2.0 * gap)  # m/s² to stop closing in within the gap
        if ttc < self.ttc_full or needed > self.escalate * self.partial_decel:
            return "full"
        if ttc < self.ttc_partial:
            return "partial"
        return False

    def step(self, obs: Observation) -> Command | Demand:
        self.pending.append(self.decide(obs))
        decision = self.pending.pop(0) if len(self.pending) > self.delay else False
        if self.braking and (not self.threats(obs) or obs.ego.speed < 0.1):
            self.braking = False  # nothing ahead to hit any more: hand back to the driver
        if decision:
            if not self.braking:
                self.interventions += 1
            self.braking = True
        if not self.braking:
            return obs.driver
        if decision == "partial":
            return Demand(-self.partial_decel)
        return Command(throttle=0.0, brake=1.0, steer=obs.driver.steer)
