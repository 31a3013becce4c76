"""Verdict tolerances at a phase boundary, and the margin plans keep: written once.

Every check of a phase's start (``at: start`` in a phase that begins after time 0)
and of its end (``at: end``, a goal reached within a ``duration``, a lane change
done) compares what the actor does with what the scenario asks within one of these
tolerances; every failure message gives the measured value, the tolerance and the
line (``docs/runner.md``, "Verdict tolerances").

They follow from the control period and the rates the runner's plans use at most:
a plan arrives at its target a **margin** of two control periods before its
deadline (one period for a command to act — controllers turn targets into inputs
after the tree's tick — and one for the response to show in the states read), so a
controller's normal lag never turns into a failure; a quantity that changes at the
largest rate a plan uses differs by that rate times one control period between two
ticks, so that is what a check one tick early or late may see:

========== ====================================================== =============
quantity    rate (what the plans use at most)                     at 20 Hz
========== ====================================================== =============
speed       3 m/s² (a car's catalogue acceleration)               0.15 m/s
position    8 m/s closing speed on a gap (``MAX_CLOSING_SPEED``)  0.40 m
lateral     3.5 m/s lateral speed (a lane change at 5 m/s²)       0.175 m
heading     1 rad/s yaw rate                                      0.05 rad
========== ====================================================== =============

A control period shorter than 50 ms does not tighten them (the physics' own
accuracy does not improve with the control rate): the period counted is at least
50 ms.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "MAX_ACCELERATION",
    "MAX_CLOSING_SPEED",
    "MAX_LATERAL_SPEED",
    "MAX_YAW_RATE",
    "MARGIN_PERIODS",
    "Tolerances",
]

#: the rates the runner's plans use at most (see the module docstring)
MAX_ACCELERATION = 3.0  # m/s²
MAX_CLOSING_SPEED = 8.0  # m/s, relative to a gap's reference
MAX_LATERAL_SPEED = 3.5  # m/s
MAX_YAW_RATE = 1.0  # rad/s
#: plans arrive this many control periods before their deadline
MARGIN_PERIODS = 2
#: the shortest period the tolerances count (s)
_FLOOR_PERIOD = 0.05


@dataclass(frozen=True, slots=True)
class Tolerances:
    """What a check at a phase boundary allows, and the plans' margin (SI units)."""

    period: float  # the control period (s)
    margin: float  # s: plans arrive this long before their deadline
    speed: float  # m/s
    position: float  # m: a gap, a distance along the road
    lateral: float  # m: from a lane's centre or a lateral position asked
    heading: float  # rad

    @classmethod
    def for_period(cls, dt: float) -> Tolerances:
        """The tolerances of a run controlled every ``dt`` seconds."""
        counted = max(dt, _FLOOR_PERIOD)
        return cls(
            period=dt,
            margin=MARGIN_PERIODS * dt,
            speed=MAX_ACCELERATION * counted,
            position=MAX_CLOSING_SPEED * counted,
            lateral=MAX_LATERAL_SPEED * counted,
            heading=MAX_YAW_RATE * counted,
        )

    def kph(self) -> str:
        """The speed tolerance as a scenario writes it (``0.54 kph``)."""
        return f"{self.speed * 3.6:.2f} kph"
