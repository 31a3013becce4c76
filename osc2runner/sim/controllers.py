"""Driver models: longitudinal speed control and lateral (Stanley) control.

Controllers are plain objects stepped once per control tick with the actor's
:class:`~osc2runner.sim.world.ActorState`; they keep their own small state
(reference, integrator) and never read a clock.

Longitudinal: a **rate profile** turns a target speed into a reference
trajectory ``(v_ref, a_ref)`` with explicit acceleration and jerk limits; a
**speed PID** tracks it and outputs a desired acceleration (feed-forward
``a_ref`` plus PI on the speed error, with integral separation and
conditional integration as anti-windup); an **inverse model** of the
vehicle turns the acceleration into throttle or brake.

Profiles (:class:`RateProfile`):

========== ===========================================================
``none``   the reference jumps to the target; the PID's own acceleration
           limits apply (+3 / -6 m/s²)
``constant`` constant acceleration ``peak`` (default 2.5 m/s²), no jerk limit
``smooth`` comfort: at most ``peak`` (default 2.5 m/s²) with jerk at most
           ``jerk`` (default 10 m/s³) on the way in and out
``asap``   full brake or full throttle (ABS / TCS keep the tires within
           the friction limit), then the PID takes over near the target
``rate_peak`` like ``smooth`` with the user's peak acceleration (required)
========== ===========================================================

Lateral: a Stanley controller on the front axle tracks a path on the
straight road, given as a lateral offset profile ``t(s)``: constant for lane
keeping, a quintic (minimum-jerk) or half-cosine blend for a lane change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from osc2check.road import Road
from osc2runner.sim.tracking import PathTracker
from osc2runner.sim.vehicle import VehicleParams
from osc2runner.sim.world import ActorState, VehicleInput

__all__ = [
    "LateralPath",
    "RATE_PROFILES",
    "RateProfile",
    "SpeedController",
    "SpeedGains",
    "StanleyController",
    "VehicleController",
]

RATE_PROFILES = ("none", "constant", "smooth", "asap", "rate_peak")

COMFORT_ACCEL = 2.5  # m/s², the `smooth` limit
COMFORT_JERK = 10.0  # m/s³, the `smooth` jerk limit


@dataclass(frozen=True, slots=True)
class RateProfile:
    """How a speed change is shaped: a profile name with optional limits.

    ``peak`` (m/s²) overrides the acceleration limit of ``constant`` and
    ``smooth`` and is required for ``rate_peak``; ``jerk`` (m/s³) overrides
    the jerk limit of ``smooth`` and ``rate_peak``.
    """

    kind: str = "none"
    peak: float | None = None
    jerk: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in RATE_PROFILES:
            raise ValueError(
                f"unknown rate profile `{self.kind}`; known: {', '.join(RATE_PROFILES)}"
            )
        if self.kind == "rate_peak" and self.peak is None:
            raise ValueError("rate profile `rate_peak` needs a peak acceleration")
        if self.peak is not None and self.peak <= 0.0:
            raise ValueError(f"peak acceleration must be > 0, got {self.peak}")
        if self.jerk is not None and self.jerk <= 0.0:
            raise ValueError(f"jerk limit must be > 0, got {self.jerk}")

    def limits(self) -> tuple[float, float]:
        """``(acceleration limit, jerk limit)`` of the reference; inf means none."""
        if self.kind in ("none", "asap"):
            return (math.inf, math.inf)
        peak = self.peak if self.peak is not None else COMFORT_ACCEL
        if self.kind == "constant":
            return (peak, math.inf)
        return (peak, self.jerk if self.jerk is not None else COMFORT_JERK)


@dataclass(frozen=True, slots=True)
class SpeedGains:
    """Speed PID gains and limits (reference/vehicle-model.md §4.2)."""

    kp: float = 1.0  # 1/s
    ki: float = 0.25  # 1/s²
    accel_max: float = 3.0  # m/s², PID output limits
    decel_max: float = 6.0
    integral_band: float = 1.0  # m/s: integrate only when |error| is below this
    reference_lead: float = 0.5  # m/s: how far the profiled reference may run ahead
    hold_brake: float = 0.3  # brake held at standstill when the target is 0
    stop_speed: float = 0.3  # m/s: below this with target 0 the car is held


def _advance_reference(
    v: float, a: float, target: float, a_max: float, j_max: float, dt: float
) -> tuple[float, float]:
    """One step of a jerk- and acceleration-limited reference towards ``target``."""
    err = target - v
    if abs(err) < 1e-9 and abs(a) <= j_max * dt:
        return target, 0.0
    want = a_max
    if math.isfinite(j_max):
        # the largest acceleration a = k*step whose discrete ramp to zero,
        # dt*(a + (a - step) + ... + step) = dt*a*(a/step + 1)/2, still fits in |err|
        step = j_max * dt
        want = min(want, 0.5 * step * (math.sqrt(1.0 + 8.0 * abs(err) / (dt * step)) - 1.0))
    want = math.copysign(min(want, abs(err) / dt), err)
    if math.isfinite(j_max):
        step = j_max * dt
        a += min(max(want - a, -step), step)
    else:
        a = want
    v_next = v + a * dt
    if (target - v_next) * err <= 0.0:  # arrives within this step: land exactly
        return target, err / dt
    return v_next, a


class SpeedController:
    """Target speed -> throttle and brake, through a rate profile, a PID and an inverse model.

    Parameters:
        params: the vehicle (mass, powertrain, brakes, resistances) for the inverse model.
        dt: control period in seconds.
        gains: PID gains and limits.
    """

    def __init__(self, params: VehicleParams, dt: float, gains: SpeedGains | None = None) -> None:
        self.params = params
        self.dt = float(dt)
        self.gains = gains or SpeedGains()
        self.target: float | None = None
        self.profile = RateProfile()
        self.v_ref: float | None = None
        self.a_ref = 0.0
        self.integral = 0.0
        self.accel_command = 0.0
        self._asap_phase: str | None = None
        self._fresh = False
        #: acceleration mode (``set_acceleration``): the reference's acceleration goal
        #: (m/s²), the jerk it is approached with and the speed bounds it stops at
        self.accel_goal: float | None = None
        self.accel_jerk = math.inf
        self.speed_bounds = (0.0, math.inf)

    def set_target(self, speed: float, profile: RateProfile | str = "none") -> None:
        """Drive towards ``speed`` (m/s, >= 0) shaped by ``profile``."""
        if speed < 0.0:
            raise ValueError(f"target speed must be >= 0, got {speed}")
        self.target = float(speed)
        self.profile = RateProfile(profile) if isinstance(profile, str) else profile
        self._asap_phase = "start" if self.profile.kind == "asap" else None
        self._fresh = True
        self.accel_goal = None

    def set_acceleration(
        self,
        accel: float,
        jerk: float = math.inf,
        bounds: tuple[float, float] = (0.0, math.inf),
    ) -> None:
        """Accelerate at ``accel`` (m/s²) from now on, reached from the current reference
        acceleration at ``jerk`` (m/s³); the speed stays within ``bounds`` (standstill
        and the top speed by default), where the acceleration ends."""
        if self.target is None or self.accel_goal is None:
            self._fresh = True
        self.accel_goal = float(accel)
        self.accel_jerk = float(jerk)
        self.speed_bounds = bounds
        self.profile = RateProfile()
        self._asap_phase = None
        self.target = bounds[1] if accel > 0.0 else bounds[0]

    def accel_reached(self, tolerance: float = 1e-6) -> bool:
        """True when the acceleration mode's reference has its goal (or is at a bound)."""
        if self.accel_goal is None:
            return False
        return abs(self.a_ref - self.accel_goal) <= tolerance or self.v_ref in self.speed_bounds

    def release(self) -> None:
        """Stop controlling: the next steps return no pedal input."""
        self.target = None
        self.v_ref = None
        self.integral = 0.0
        self.accel_goal = None

    def reached(self, state: ActorState, tolerance: float = 0.3) -> bool:
        """True when the reference is at the target and the speed within ``tolerance``."""
        if self.target is None:
            return False
        return self.v_ref == self.target and abs(state.speed - self.target) <= tolerance

    def step(self, state: ActorState) -> tuple[float, float]:
        """One control tick: ``(throttle, brake)`` for the actor's current state."""
        if self.target is None:
            return (0.0, 0.0)
        g = self.gains
        v = state.speed
        target = self.target

        if self._asap_phase is not None:
            pedals = self._asap(state)
            if pedals is not None:
                return pedals

        if self.v_ref is None or (self._fresh and abs(self.v_ref - v) > g.reference_lead):
            # a new target starts from the current reference when the car is on it,
            # otherwise (first target, car placed or released meanwhile) from the car
            self.v_ref, self.a_ref, self.integral = v, 0.0, 0.0
        self._fresh = False
        if self.accel_goal is not None:
            self._advance_acceleration()
        elif self.profile.kind == "none":
            self.v_ref, self.a_ref = target, 0.0
        else:
            a_max, j_max = self.profile.limits()
            # a car held back (by friction, power or the brake ramp) more than
            # `reference_lead` behind its reference re-anchors the reference on
            # itself, with the acceleration it actually achieves
            if (self.v_ref - v) * self.a_ref > g.reference_lead * abs(self.a_ref):
                self.v_ref = v
                self.a_ref = math.copysign(min(abs(state.accel), a_max), self.a_ref)
            self.v_ref, self.a_ref = _advance_reference(
                self.v_ref, self.a_ref, target, a_max, j_max, self.dt
            )

        if target <= 0.0 and self.v_ref <= 0.0 and v < g.stop_speed:
            self.integral = 0.0
            self.accel_command = 0.0
            return (0.0, g.hold_brake)

        err = self.v_ref - v
        unclamped = self.a_ref + g.kp * err + g.ki * self.integral
        saturated = (unclamped > g.accel_max and err > 0.0) or (
            unclamped < -g.decel_max and err < 0.0
        )
        # anti-windup: integrate only on a steady reference (integral separation in
        # time), close to it (in speed), and when the output is not saturated
        steady = self.a_ref == 0.0 or self.accel_goal is not None
        if steady and abs(err) < g.integral_band and not saturated:
            self.integral += err * self.dt
            unclamped = self.a_ref + g.kp * err + g.ki * self.integral
        accel = min(max(unclamped, -g.decel_max), g.accel_max)
        self.accel_command = accel
        return self.pedals_for(accel, v)

    def _advance_acceleration(self) -> None:
        """One step of the acceleration mode: the reference acceleration moves to the goal
        at the jerk limit, the reference speed integrates it within the bounds."""
        assert self.accel_goal is not None and self.v_ref is not None
        step = self.accel_jerk * self.dt
        self.a_ref += min(max(self.accel_goal - self.a_ref, -step), step)
        low, high = self.speed_bounds
        v = self.v_ref + self.a_ref * self.dt
        if v <= low or v >= high:
            v, self.a_ref = min(max(v, low), high), 0.0
        self.v_ref = v

    def pedals_for(self, accel: float, speed: float) -> tuple[float, float]:
        """Inverse vehicle model: the ``(throttle, brake)`` giving ``accel`` at ``speed``."""
        p = self.params
        force = p.mass * accel + p.resistance_force(speed)
        if force >= 0.0:
            return (min(force / p.drive_force_available(speed), 1.0), 0.0)
        return (0.0, min(-force * p.wheel_radius / p.max_brake_torque, 1.0))

    def _asap(self, state: ActorState) -> tuple[float, float] | None:
        """Full pedal until close to the target, then hand over to the PID."""
        target = self.target
        assert target is not None
        v = state.speed
        p = self.params
        if self._asap_phase == "start":
            self._asap_phase = "brake" if v > target else "throttle"
        if self._asap_phase == "brake":
            # release early by half the pedal ramp, so the speed lands on the target
            lead = 0.5 * abs(state.accel) / p.brake_rate
            if target <= 0.0 or v - target > lead:
                if target <= 0.0 and v < self.gains.stop_speed:
                    self._asap_phase = None
                    self.v_ref, self.a_ref = 0.0, 0.0
                    return (0.0, 1.0)
                return (0.0, 1.0)
        elif self._asap_phase == "throttle":
            lead = 0.5 * abs(state.accel) / p.throttle_rate
            if target - v > lead:
                return (1.0, 0.0)
        self._asap_phase = None
        self.v_ref, self.a_ref, self.integral = target, 0.0, 0.0
        return None


# ---------------------------------------------------------------------- lateral


@dataclass(frozen=True, slots=True)
class LateralPath:
    """A path on the straight road: lateral offset ``t`` as a function of ``s``.

    ``t`` blends from ``t0`` at ``s0`` to ``t1`` at ``s1`` (constant outside).
    ``shape`` is ``smooth`` (quintic, minimum jerk: zero lateral velocity
    and acceleration at both ends) or ``sinusoidal`` (half cosine).
    """

    t0: float
    t1: float
    s0: float = 0.0
    s1: float = 0.0
    shape: str = "smooth"

    def __post_init__(self) -> None:
        if self.shape not in ("smooth", "sinusoidal"):
            raise ValueError(f"unknown lateral shape `{self.shape}`; known: smooth, sinusoidal")

    @classmethod
    def constant(cls, t: float) -> LateralPath:
        return cls(t, t)

    def at(self, s: float) -> tuple[float, float]:
        """``(t, dt/ds)`` at ``s``."""
        length = self.s1 - self.s0
        if self.t0 == self.t1 or length <= 0.0 or s >= self.s1:
            return (self.t1, 0.0)
        if s <= self.s0:
            return (self.t0, 0.0)
        u = (s - self.s0) / length
        dt = self.t1 - self.t0
        if self.shape == "smooth":
            blend = u * u * u * (10.0 + u * (-15.0 + 6.0 * u))
            slope = 30.0 * u * u * (1.0 - u) * (1.0 - u)
        else:
            blend = 0.5 * (1.0 - math.cos(math.pi * u))
            slope = 0.5 * math.pi * math.sin(math.pi * u)
        return (self.t0 + dt * blend, dt * slope / length)


class StanleyController:
    """Lateral control on the front axle: ``delta = heading error - atan(k e / (v + v_soft))``.

    Parameters:
        params: the vehicle (front axle position, maximum steer angle).
        road: the road whose ``(s, t)`` frame paths are given in.
        gain: cross-track gain ``k`` (1/s).
        soft_speed: ``v_soft`` (m/s), keeps the gain finite at low speed.
    """

    def __init__(
        self, params: VehicleParams, road: Road, gain: float = 1.0, soft_speed: float = 1.0
    ) -> None:
        self.params = params
        self.road = road
        self.gain = gain
        self.soft_speed = soft_speed
        self.path: LateralPath | None = None
        self.error = 0.0  # last cross-track error of the front axle, m (positive: left of path)

    def keep_lane(self, lane: int, offset: float = 0.0) -> None:
        """Follow the centre of ``lane`` (plus ``offset`` m to the left)."""
        self.path = LateralPath.constant(self.road.lane_center_t(lane) + offset)

    def keep_offset(self, t: float) -> None:
        """Follow the line at lateral road coordinate ``t``."""
        self.path = LateralPath.constant(t)

    def change_lane(
        self,
        state: ActorState,
        lane: int,
        *,
        offset: float = 0.0,
        distance: float | None = None,
        duration: float | None = None,
        shape: str = "smooth",
    ) -> LateralPath:
        """Move from the current lateral position to ``lane`` over a distance or duration.

        With ``duration`` the distance is ``duration * speed`` at the start.
        Returns the path now followed.
        """
        target = self.road.lane_center_t(lane) + offset
        return self.move_to(state, target, distance=distance, duration=duration, shape=shape)

    def move_to(
        self,
        state: ActorState,
        t: float,
        *,
        distance: float | None = None,
        duration: float | None = None,
        shape: str = "smooth",
    ) -> LateralPath:
        """Move from the current lateral position to road coordinate ``t`` over a distance
        or a duration (the distance is ``duration * speed`` at the start)."""
        if distance is None:
            if duration is None:
                raise ValueError("a lateral move needs a distance or a duration")
            distance = duration * max(state.speed, 1.0)
        s_front, t_front = self._front(state)
        t_now = self.path.at(s_front)[0] if self.path is not None else t_front
        self.path = LateralPath(t_now, t, s_front, s_front + distance, shape)
        return self.path

    def done(self, state: ActorState) -> bool:
        """True once the front axle has passed the end of the current path's blend."""
        return self.path is not None and self._front(state)[0] >= self.path.s1

    def step(self, state: ActorState) -> float:
        """One control tick: the steer input in [-1, 1] (0 without a path)."""
        if self.path is None:
            return 0.0
        s, t = self._front(state)
        t_ref, slope = self.path.at(s)
        self.error = (t - t_ref) * math.cos(math.atan(slope))
        path_yaw = self.road.heading + math.atan(slope)
        heading_error = (path_yaw - state.yaw + math.pi) % (2.0 * math.pi) - math.pi
        delta = heading_error - math.atan2(
            self.gain * self.error, self.soft_speed + abs(state.speed)
        )
        return min(max(delta / self.params.max_steer, -1.0), 1.0)

    def _front(self, state: ActorState) -> tuple[float, float]:
        d = self.params.front_axle_x
        x = state.x + d * math.cos(state.yaw)
        y = state.y + d * math.sin(state.yaw)
        return self.road.to_st(x, y)


class VehicleController:
    """A speed controller and a Stanley controller driving one vehicle."""

    def __init__(self, params: VehicleParams, road: Road, dt: float) -> None:
        self.params = params
        self.speed = SpeedController(params, dt)
        self.lateral = StanleyController(params, road)
        #: a world path being followed (``follow_path``...): steers instead of ``lateral``
        self.path: PathTracker | None = None

    def step(self, state: ActorState) -> VehicleInput:
        """One control tick: the vehicle's inputs."""
        throttle, brake = self.speed.step(state)
        if self.path is not None:
            steer = self.path.step(state.x, state.y, state.yaw, state.speed)
        else:
            steer = self.lateral.step(state)
        return VehicleInput(throttle, brake, steer)
