"""Kinematic vehicles: the lighter model for background traffic, chosen per actor.

A kinematic vehicle has no body in the MuJoCo model. Its driver's inputs go through
the same actuator layer as a multibody vehicle's (``sim/actuators.py``: pedal and
steering rate limits, drive force and power, brake torques, ABS and TCS caps from
the tires' friction and the estimated wheel loads, rolling resistance), and the
forces that layer asks for move it once per control step:

* **Along the heading**: ``m a = F_drive - F_brake - F_drag``, with ``F_drive`` and
  ``F_brake`` the layer's wheel torques over the wheel radius (the brakes and the
  rolling resistance act like Coulomb friction: they stop the vehicle and hold it,
  they never push it backwards) and ``F_drag`` the aerodynamic drag. The forces are
  held over the control step (exact integration of a constant acceleration; a
  vehicle that comes to rest within the step stays at rest until the next one).
* **Across it**: the kinematic bicycle at the centre of gravity: yaw rate
  ``u tan(delta) / L`` and side slip ``lr tan(delta) / L``, with the yaw rate capped
  so the lateral acceleration stays within the tires' mean friction times g (a
  kinematic vehicle turns at the grip's limit where a multibody one would slide).

What it leaves out: tire slip and its dynamics, suspension, pitch and roll, load
transfer felt by the body (the layer still estimates it for ABS and TCS), the
wheels' rotating inertia, physical contacts, trailers. Its reported pose is the
bounding-box centre, like a multibody vehicle's; wheel speeds are its speed, wheel
loads the layer's estimate. The figures comparing it with the multibody model are in
``docs/world.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from osc2runner.sim.state import ActorSpec
from osc2runner.sim.vehicle_bank import DrivenBank, four

__all__ = ["KinematicBank"]

GRAVITY = 9.81


def _col(values: Sequence[float]) -> np.ndarray:
    return np.asarray(values, dtype=float)


class KinematicBank(DrivenBank):
    """The kinematic vehicles of one world, in world order (see the module's docstring).

    Parameters:
        specs: the vehicles' specs.
        index: each vehicle's position among all the world's actors.
        dt: the control period (s).
    """

    def __init__(self, specs: Sequence[ActorSpec], index: Sequence[int], dt: float) -> None:
        super().__init__(specs, index, dt)
        params = self.params
        self.mass = _col([p.mass for p in params])
        self.wheelbase = _col([p.wheelbase for p in params])
        self.lr = _col([p.lr for p in params])  # CoG to the rear axle
        self.cog_x = _col([p.cog_x for p in params])  # CoG ahead of the box centre
        n = self.count
        self.pos = np.zeros((n, 2))
        self.yaw = np.zeros(n)
        self.cos, self.sin = np.ones(n), np.zeros(n)  # of the yaw
        self.grip = np.full(n, GRAVITY)  # the lateral acceleration the tires allow
        self.speed = np.zeros(n)  # along the heading (m/s)
        self.lat_speed = np.zeros(n)  # of the box centre, left of the heading
        self.yaw_rate = np.zeros(n)

    def reset(self) -> None:
        """No input applied, nothing travelled, at rest."""
        super().reset()
        self.speed = np.zeros(self.count)
        self.lat_speed = np.zeros(self.count)
        self.yaw_rate = np.zeros(self.count)

    def place(self, row: int, x: float, y: float, yaw: float, speed: float) -> None:
        """Put vehicle ``row`` at ``(x, y)`` heading ``yaw`` at ``speed`` along it."""
        self.pos[row] = (x, y)
        self.yaw[row] = yaw
        self.cos[row], self.sin[row] = math.cos(yaw), math.sin(yaw)
        self.speed[row] = speed
        self.lat_speed[row] = self.yaw_rate[row] = self.accel[row] = 0.0

    def step(self) -> None:
        """Run the actuator layer on this tick's inputs and move every vehicle over one
        control step (numpy's cost is per call on arrays of a few vehicles: the common
        case, every vehicle moving and none stopping, takes the fewest calls)."""
        if not self.count:
            return
        bank, dt = self.actuators, self.dt
        u = self.speed
        bank.update(u, self.mu, self.accel, u * self.yaw_rate)
        drive = bank.drive_torque.sum(axis=1)
        drive /= bank.radius
        drive -= bank.drag * u * np.abs(u)
        resist = bank.brake_torque.sum(axis=1)  # brakes and rolling resistance
        resist /= bank.radius
        direction = np.sign(u)
        rest = direction == 0.0
        if rest.any():  # at rest: moves off only when the drive overcomes the resistance
            direction[rest] = np.sign(drive[rest])
            drive[rest & (np.abs(drive) <= resist)] = 0.0
        accel = (drive - direction * resist) / self.mass
        u1 = u + accel * dt
        travelled = (u + u1) * (0.5 * dt)
        stops = u1 * direction < 0.0
        if stops.any():  # the resistance stops it within the step: to rest, then at rest
            u1[stops] = 0.0
            travelled[stops] = -0.5 * u[stops] * u[stops] / accel[stops]
        # across: the kinematic bicycle at the centre of gravity, within the tires' grip
        fastest = np.maximum(np.abs(u), np.abs(u1))  # the cap holds all through the step
        limit = self.grip / np.maximum(fastest * fastest, 1e-9)
        curvature = np.tan(bank.delta) / self.wheelbase
        np.minimum(curvature, limit, out=curvature)
        np.maximum(curvature, -limit, out=curvature)
        turned = curvature * travelled  # yaw change over the step
        side = self.lr * curvature  # lateral per longitudinal metre, at the CoG
        heading = self.yaw + 0.5 * turned
        c, s = np.cos(heading), np.sin(heading)
        yaw = self.yaw + turned
        cos1, sin1 = np.cos(yaw), np.sin(yaw)
        # the box centre: to the CoG, along the path, back from the new CoG
        x = self.pos[:, 0] + self.cog_x * self.cos + travelled * (c - side * s) - self.cog_x * cos1
        y = self.pos[:, 1] + self.cog_x * self.sin + travelled * (s + side * c) - self.cog_x * sin1
        self.pos = np.column_stack((x, y))
        self.yaw = np.arctan2(sin1, cos1)
        self.cos, self.sin = cos1, sin1
        self.yaw_rate = curvature * u1
        self.lat_speed = (side - self.cog_x * curvature) * u1
        self.accel = (u1 - u) / dt
        self.speed = u1
        self.distance += np.abs(travelled)

    def write_friction(self) -> None:
        """Put the per-tire friction in effect: the grip that caps the lateral
        acceleration is the tires' mean friction times g."""
        super().write_friction()
        self.grip = np.asarray(self.mu_mean) * GRAVITY

    def wheel_loads(self, row: int) -> tuple[float, float, float, float]:
        """The actuator layer's estimate of each tire's normal load (N) of vehicle ``row``."""
        loads = self.actuators.estimate_loads(self.accel, self.speed * self.yaw_rate)
        return four(loads[row])

    def wheel_speeds(self, row: int) -> tuple[float, float, float, float]:
        """Each wheel's speed (m/s) of vehicle ``row``: its speed (no slip, no turn)."""
        speed = float(self.speed[row])
        return (speed, speed, speed, speed)

    def state_array(self) -> np.ndarray:
        """Every number of the bank that determines the future (for replay checks)."""
        bank = self.actuators
        return np.concatenate(
            [
                self.pos.ravel(),
                self.yaw,
                self.speed,
                self.yaw_rate,
                self.accel,
                bank.throttle,
                bank.brake,
                bank.delta,
                self.mu.ravel(),
            ]
        )
