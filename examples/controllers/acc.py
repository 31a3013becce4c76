"""An adaptive cruise control (ACC): the second example system under test.

It holds the scenario's set speed (``Observation.intent.speed``) and, behind
a slower actor in its path, a time gap of ``time_gap`` (1.8 s) plus
``standstill`` (4 m), with comfort limits on acceleration (``max_accel``
1.5 m/s²) and braking (``max_decel`` 3.5 m/s², an ACC never brakes harder;
an emergency is the AEB's job). Steering is the scenario's driver model's:
the ACC returns a :class:`~osc2runner.sut.Demand` with an acceleration only.

    osc2run examples/ncap/ccrm.osc --sut examples/controllers/acc.py:Acc
"""

from __future__ import annotations

from osc2runner.sut import Demand, Observation, SutInfo


class Acc:
    """Speed and time-gap control (see the module docstring)."""

    time_gap = 1.8  # s
    standstill = 4.0  # m
    max_accel = 1.5  # m/s²
    max_decel = 3.5  # m/s²
    speed_gain = 0.4  # 1/s
    gap_gain = 0.23  # 1/s²
    closing_gain = 0.7  # 1/s

    def reset(self, info: SutInfo) -> None:
        self.info = info

    def step(self, obs: Observation) -> Demand:
        v = obs.ego.speed
        set_speed = obs.intent.speed if obs.intent.speed is not None else v
        accel = self.speed_gain * (set_speed - v)
        lead = obs.ahead()
        if lead is not None:
            desired = self.standstill + self.time_gap * v
            follow = self.gap_gain * (lead.gap - desired) + self.closing_gain * lead.rel_vx
            accel = min(accel, follow)
        return Demand(min(max(accel, -self.max_decel), self.max_accel))
