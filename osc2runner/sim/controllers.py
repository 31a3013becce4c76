"""Driver models: longitudinal speed control and lateral (Stanley) control.

Controllers are plain objects stepped once per control tick with the actor's
:class:`~osc2runner.sim.state.ActorState`; they keep their own small state
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

Lateral: a Stanley controller on the front axle follows the centre line of a
route of lanes (:meth:`RoadNetwork.route <osc2check.world.network.RoadNetwork.route>`:
its lane through lane sections, road links and junctions, the forks taken
towards the roads it is told to pass, else with its seed), at an offset given
as a profile along that centre line (:class:`LateralPath`): constant for lane
keeping, a quintic (minimum-jerk) or half-cosine blend for a lane change or a
lateral move. A lane change blends to the target lane's centre as it lies at
each point of the way (lanes of any width, widths that change), then follows
the target lane's own route. The steering angle is Stanley's, with a
curvature feed-forward (see :class:`StanleyController`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from osc2check.world.arrays import FloatArray
from osc2check.world.carriageways import carriageways, lane_at
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.paths import LanePath
from osc2check.world.projection import lane_centre
from osc2check.world.topology import neighbour_n, side_neighbour
from osc2check.world.tracking import PathCursor
from osc2runner.sim.state import ActorState, VehicleInput
from osc2runner.sim.tracking import PathTracker, stanley_steer
from osc2runner.sim.trailer import TrailerParams
from osc2runner.sim.vehicle import VehicleParams

__all__ = [
    "LateralPath",
    "RATE_PROFILES",
    "RateProfile",
    "SpeedController",
    "SpeedGains",
    "StanleyController",
    "VehicleController",
    "resolve_lane",
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
        #: the trailer the vehicle tows: the inverse model adds its mass and resistance
        self.towed: TrailerParams | None = None

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
        feed = self._feed_forward(v, target)
        unclamped = feed + g.kp * err + g.ki * self.integral
        saturated = (unclamped > g.accel_max and err > 0.0) or (
            unclamped < -g.decel_max and err < 0.0
        )
        # anti-windup: integrate only on a steady reference (integral separation in
        # time), close to it (in speed), and when the output is not saturated
        steady = self.a_ref == 0.0 or self.accel_goal is not None
        if steady and abs(err) < g.integral_band and not saturated:
            self.integral += err * self.dt
            unclamped = feed + g.kp * err + g.ki * self.integral
        accel = min(max(unclamped, -g.decel_max), g.accel_max)
        self.accel_command = accel
        return self.pedals_for(accel, v)

    def _feed_forward(self, speed: float, target: float) -> float:
        """The reference's acceleration, let go of early at the end of a ramp without a
        jerk limit: the pedal cannot follow the acceleration's drop to zero at once, so
        it is released half its ramp before the reference arrives (as ``asap`` does),
        and the car lands on the target instead of running past it by about
        a²/(2·jerk) (0.2 m/s at a car's 2.5 m/s²: more than the speed tolerance)."""
        a = self.a_ref
        if a == 0.0 or self.accel_goal is not None or math.isfinite(self.profile.limits()[1]):
            return a
        p = self.params
        mass = p.mass + (self.towed.mass if self.towed is not None else 0.0)
        if a > 0.0:  # the jerk at which the pedal in use lets the acceleration go
            jerk = p.throttle_rate * p.drive_force_available(speed) / mass
        else:
            jerk = p.brake_rate * p.max_brake_torque / p.wheel_radius / mass
        # the reference is already a tick ahead of the speed it is compared with
        arrives_in = (target - (self.v_ref or 0.0)) / a + self.dt
        return 0.0 if arrives_in <= 0.5 * abs(a) / jerk else a

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
        """Inverse vehicle model: the ``(throttle, brake)`` giving ``accel`` at ``speed``
        (with the trailer it tows, whose brakes, if any, add to its own)."""
        p = self.params
        force = p.mass * accel + p.resistance_force(speed)
        towed = self.towed
        if towed is not None:
            force += towed.mass * accel + towed.resistance_force(speed)
            if force < 0.0 and towed.braked:  # the trailer's brakes follow the pedal
                full = p.max_brake_torque / p.wheel_radius
                full += towed.max_brake_torque / towed.wheel_radius
                return (0.0, min(-force / full, 1.0))
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

#: how far ahead a route of lanes is planned (m), and how close to its end it is renewed
ROUTE_LENGTH = 1500.0
ROUTE_RENEW = 300.0


@dataclass(frozen=True, eq=False)
class LateralPath:
    """An offset from the followed centre line (m, left positive) along its distance ``d``.

    The offset blends from ``o0`` at ``d0`` to ``o1`` at ``d1`` (constant outside).
    ``shape`` is ``smooth`` (quintic, minimum jerk: zero lateral velocity and
    acceleration at both ends) or ``sinusoidal`` (half cosine). A lane change's end
    offset is where the target lane's centre lies at each point: then ``goal_d`` and
    ``goal_o`` tabulate it (``o1`` is unused).
    """

    o0: float
    o1: float
    d0: float = 0.0
    d1: float = 0.0
    shape: str = "smooth"
    goal_d: FloatArray | None = None
    goal_o: FloatArray | None = None

    def __post_init__(self) -> None:
        if self.shape not in ("smooth", "sinusoidal"):
            raise ValueError(f"unknown lateral shape `{self.shape}`; known: smooth, sinusoidal")

    @classmethod
    def constant(cls, offset: float) -> LateralPath:
        return cls(offset, offset)

    def goal(self, d: float) -> tuple[float, float]:
        """The end offset at ``d`` and its slope."""
        if self.goal_d is None or self.goal_o is None:
            return (self.o1, 0.0)
        gd, go = self.goal_d, self.goal_o
        value = float(np.interp(d, gd, go))
        j = int(np.clip(np.searchsorted(gd, d) - 1, 0, len(gd) - 2)) if len(gd) > 1 else 0
        span = float(gd[j + 1] - gd[j]) if len(gd) > 1 else 0.0
        slope = float(go[j + 1] - go[j]) / span if span > 0.0 and gd[0] <= d <= gd[-1] else 0.0
        return (value, slope)

    def at(self, d: float) -> tuple[float, float]:
        """``(offset, d offset / d d)`` at distance ``d``."""
        goal, goal_slope = self.goal(d)
        length = self.d1 - self.d0
        if length <= 0.0 or d >= self.d1:
            return (goal, goal_slope)
        if d <= self.d0:
            return (self.o0, 0.0)
        u = (d - self.d0) / length
        if self.shape == "smooth":
            blend = u * u * u * (10.0 + u * (-15.0 + 6.0 * u))
            rate = 30.0 * u * u * (1.0 - u) * (1.0 - u)
        else:
            blend = 0.5 * (1.0 - math.cos(math.pi * u))
            rate = 0.5 * math.pi * math.sin(math.pi * u)
        change = goal - self.o0
        return (self.o0 + change * blend, change * rate / length + goal_slope * blend)


def resolve_lane(network: RoadNetwork, lane: LaneRef | int, state: ActorState | None) -> LaneRef:
    """The lane ``lane`` names: itself, or the lane of that OSC2 number (1 = rightmost in
    the direction of travel) where ``state`` is, else on the map's first carriageway."""
    if isinstance(lane, LaneRef):
        return lane
    if state is not None and state.road is not None and state.direction:
        return network.lane_from_osc2_index(state.road, state.s, lane, state.direction)
    return lane_at(network, carriageways(network)[0], 0.0, lane)


class StanleyController:
    """Lateral control on the front axle along a route of lane centre lines.

    The steering angle is :func:`~osc2runner.sim.tracking.stanley_steer`'s: Stanley's
    law with the line's curvature fed forward. ``e`` is the front axle's distance left
    of the line to follow (the route's centre line moved by the offset profile), the
    line's heading is taken where the front axle projects onto it, and its curvature
    there (the centre line's, at the offset).

    Parameters:
        params: the vehicle (wheelbase, front axle position, maximum steer angle).
        network: the map whose lanes are followed.
        gain: cross-track gain ``k`` (1/s).
        soft_speed: ``v_soft`` (m/s), keeps the gain finite at low speed.
        seed: picks the forks of the route nothing else decides.
    """

    def __init__(
        self,
        params: VehicleParams,
        network: RoadNetwork,
        gain: float = 1.0,
        soft_speed: float = 1.0,
        seed: int = 0,
    ) -> None:
        self.params = params
        self._wheelbase = params.wheelbase  # a property: read once, used every tick
        self.network = network
        self.gain = gain
        self.soft_speed = soft_speed
        self.seed = seed
        self.route: LanePath | None = None  # the lane centre lines followed
        self.path: LateralPath | None = None  # the offset along them (None: no control)
        self.error = 0.0  # last cross-track error of the front axle, m (positive: left of path)
        self.towards: list[str] = []  # roads the route is to pass, in order
        self.on_route: Callable[[LanePath | None], None] | None = None  # told of new routes
        self._cursor: PathCursor | None = None
        self._renewable = False
        self._then: float | None = None  # after a lane change: the offset to keep in the new lane
        self._distance = 0.0  # the front axle's distance along the route at the last step

    # ---- the route

    def set_route(self, towards: Sequence[str]) -> None:
        """Pass the roads ``towards`` (ids, in order) at the next forks."""
        self.towards = list(towards)

    def _follow(self, lane: LaneRef) -> None:
        towards = list(self.towards)
        while towards and towards[0] == lane.road:
            towards.pop(0)
        self.towards = towards
        route = self.network.route(lane, seed=self.seed, max_length=ROUTE_LENGTH, towards=towards)
        self.route = route.path
        self._renewable = route.end == "length"
        self._cursor = PathCursor(route.path)
        if self.on_route is not None:
            self.on_route(route.path)

    def keep_lane(
        self, lane: LaneRef | int, offset: float = 0.0, state: ActorState | None = None
    ) -> None:
        """Follow the centre of ``lane`` (plus ``offset`` m to the left) along its route;
        a lane number counts from the right where the vehicle is (``state``), or on the
        map's first carriageway."""
        self._follow(resolve_lane(self.network, lane, state))
        self.path = LateralPath.constant(offset)
        self._then = None

    def hold(self, state: ActorState) -> None:
        """Keep the lane the vehicle is in, at its offset from the lane centre now."""
        ref = state.lane_ref
        if ref is None or not self.network.lane(ref).drivable:
            return
        self.keep_lane(ref, state.offset if math.isfinite(state.offset) else 0.0)

    def keep_offset(self, offset: float) -> None:
        """Follow the current lane at ``offset`` m left of its centre."""
        self.path = LateralPath.constant(offset)

    def change_lane(
        self,
        state: ActorState,
        lane: LaneRef | int,
        *,
        offset: float = 0.0,
        distance: float | None = None,
        duration: float | None = None,
        shape: str = "smooth",
    ) -> LateralPath:
        """Move from the current lateral position to ``lane`` (plus ``offset``) over a
        distance or a duration (the distance is ``duration * speed`` at the start).

        ``lane`` is a lane of the road the vehicle is on, or its number counted from the
        right there. Returns the offset profile now followed.
        """
        target = resolve_lane(self.network, lane, state)
        here = state.lane_ref
        if self.route is None or here is None:
            self.keep_lane(target, offset)
            return self.path  # type: ignore[return-value]
        side, count = self._steps(here, target)
        if count == 0:
            return self.move_to(state, offset, distance=distance, duration=duration, shape=shape)
        distance = self._distance_of(state, distance, duration)
        d_front, o_now = self._front_offset(state)
        goal_d, goal_o = self._goal(side, count, d_front, d_front + distance + 50.0)
        self.path = LateralPath(
            o_now,
            offset,
            d_front,
            d_front + distance,
            shape,
            goal_d,
            goal_o + offset,
        )
        self._then = offset
        return self.path

    def move_to(
        self,
        state: ActorState,
        offset: float,
        *,
        distance: float | None = None,
        duration: float | None = None,
        shape: str = "smooth",
    ) -> LateralPath:
        """Move from the current lateral position to ``offset`` m left of the current lane's
        centre over a distance or a duration (the distance is ``duration * speed``)."""
        if self.route is None:
            self.hold(state)
        distance = self._distance_of(state, distance, duration)
        d_front, o_now = self._front_offset(state)
        self.path = LateralPath(o_now, offset, d_front, d_front + distance, shape)
        self._then = None
        return self.path

    def done(self, state: ActorState) -> bool:
        """True once the front axle has passed the end of the current blend."""
        if self.path is None:
            return False
        if self._then is not None:
            return False
        return self._front_offset(state)[0] >= self.path.d1

    # ---- stepping

    def step(self, state: ActorState) -> float:
        """One control tick: the steer input in [-1, 1] (0 without a path)."""
        if self.path is None or self.route is None or self._cursor is None:
            return 0.0
        front, yaw = self.params.front_axle_x, state.yaw
        fx, fy = state.x + front * math.cos(yaw), state.y + front * math.sin(yaw)
        point = self._cursor.locate(fx, fy)
        if self._then is not None and point.distance >= self.path.d1:
            self._switch(state)
            point = self._cursor.locate(fx, fy)
        elif self._renewable and point.distance > self._cursor.length - ROUTE_RENEW:
            self._renew(state)
            point = self._cursor.locate(fx, fy)
        self._distance = point.distance
        offset, slope = self.path.at(point.distance)
        self.error = (point.offset - offset) * math.cos(math.atan(slope))
        kappa = point.curvature / max(1.0 - point.curvature * offset, 0.1)
        delta = stanley_steer(
            self._wheelbase,
            kappa,
            point.heading + math.atan(slope),
            yaw,
            self.error,
            self.gain,
            self.soft_speed,
            state.speed,
        )
        return min(max(delta / self.params.max_steer, -1.0), 1.0)

    # ---- helpers

    def _front(self, state: ActorState) -> tuple[float, float]:
        return self.params.front_axle(state.x, state.y, state.yaw)

    def _front_offset(self, state: ActorState) -> tuple[float, float]:
        """The front axle's distance along the route and the offset it follows there now."""
        assert self._cursor is not None
        fx, fy = self._front(state)
        point = self._cursor.locate(fx, fy)
        if self.path is None:
            return point.distance, point.offset
        return point.distance, self.path.at(point.distance)[0]

    @staticmethod
    def _distance_of(state: ActorState, distance: float | None, duration: float | None) -> float:
        if distance is not None:
            return max(distance, 0.1)
        if duration is None:
            raise ValueError("a lateral move needs a distance or a duration")
        return max(duration * max(state.speed, 1.0), 0.1)

    def _steps(self, here: LaneRef, target: LaneRef) -> tuple[int, int]:
        """``(side, count)``: ``target`` is ``count`` lanes to the left (+1) or right (-1)
        of ``here``, in ``here``'s direction of travel, in one lane section."""
        if target == here:
            return (1, 0)
        direction = self.network.lane(here).direction
        for side in (1, -1):
            other = here
            for count in range(1, 20):
                found = side_neighbour(self.network, other, side * direction)
                if found is None:
                    break
                other = found
                if other == target or (other.road, other.lane) == (target.road, target.lane):
                    return (side, count)
        raise ValueError(f"{target} is not beside {here}")

    def _goal(self, side: int, count: int, d0: float, d1: float) -> tuple[FloatArray, FloatArray]:
        """Where the centre of the lane ``count`` lanes to ``side`` lies, left of the
        route's centre line, at the route's points from ``d0`` to ``d1``."""
        route = self.route
        assert route is not None
        lo = max(int(np.searchsorted(route.distance, d0)) - 1, 0)
        hi = min(int(np.searchsorted(route.distance, d1)) + 1, len(route.distance))
        distance = route.distance[lo:hi]
        gap = np.full(len(distance), np.nan)
        lane_of = route.lane_of[lo:hi]
        for k in np.unique(lane_of):
            ref: LaneRef | None = route.lanes[int(k)]
            assert ref is not None
            direction = self.network.lane(ref).direction
            ref = neighbour_n(self.network, ref, side * direction, count)
            if ref is None:
                continue
            mask = lane_of == k
            centre, _ = lane_centre(self.network, ref, route.s[lo:hi][mask])
            gap[mask] = (centre - route.t[lo:hi][mask]) * direction
        valid = ~np.isnan(gap)
        if not valid.any():
            raise ValueError("there is no lane on that side")
        gap = np.interp(distance, distance[valid], gap[valid])
        return distance.copy(), gap

    def _switch(self, state: ActorState) -> None:
        """A lane change is complete: follow the target lane's own route."""
        offset = self._then
        assert offset is not None
        here = state.lane_ref
        self._then = None
        if here is None:
            self.path = LateralPath.constant(offset)
            return
        self.keep_lane(here, offset)

    def _renew(self, state: ActorState) -> None:
        """Plan the route on from the lane the vehicle is in, keeping the offset."""
        ref = state.lane_ref
        if ref is None or self.path is None:
            self._renewable = False
            return
        path = self.path
        self._follow(ref)
        if path.d1 <= self._distance:
            self.path = LateralPath.constant(path.at(self._distance)[0])


class VehicleController:
    """A speed controller and a Stanley controller driving one vehicle."""

    def __init__(
        self, params: VehicleParams, network: RoadNetwork, dt: float, seed: int = 0
    ) -> None:
        self.params = params
        self.speed = SpeedController(params, dt)
        self.lateral = StanleyController(params, network, seed=seed)
        #: a world path being followed (``follow_path``...): steers instead of ``lateral``
        self.path: PathTracker | None = None

    def step(self, state: ActorState) -> VehicleInput:
        """One control tick: the vehicle's inputs."""
        throttle, brake = self.speed.step(state)
        if self.path is not None:
            steer = self.path.step(state.x, state.y, state.yaw, state.speed, self.speed.target)
        else:
            steer = self.lateral.step(state)
        return VehicleInput(throttle, brake, steer)
