"""The actuator layer ("ECU") between driver inputs and the vehicle model.

Once per control tick each vehicle receives ``throttle`` in [0, 1], ``brake``
in [0, 1] and ``steer`` in [-1, 1]. The layer turns them into joint torques
and steering angles, the way a car's electronics would
(reference/vehicle-model.md §2.2):

* **Rate limits**: pedals move at most ``throttle_rate`` / ``brake_rate`` per
  second (the brake ramp is the pressure build-up, 0 -> 1 in about 0.17 s);
  the road-wheel angle moves at most ``steer_rate`` rad/s.
* **Drive**: total force ``throttle * min(F_max, P_max / v)`` split equally
  over the driven wheels (an open differential).
* **Traction control (TCS)**: each driven wheel's torque is capped at
  ``tcs_margin * mu * N * r``.
* **Brakes**: torque per wheel ``brake * T_max * share`` (front/rear split),
  applied as Coulomb friction on the spin joint.
* **ABS**: each wheel's brake torque is capped at ``abs_margin * mu * N * r``,
  so tires stay below the friction limit (a sliding MuJoCo contact hops,
  see the reference's §6.4).
* **Rolling resistance**: a constant ``c_rr * N_static * r`` spin friction on
  every wheel, which also holds a stopped car; aerodynamic drag is a force.
* **Ackermann**: the road-wheel angle is split into left/right angles.

Everything is vectorised over all vehicles of a world (numpy arrays with one
row per vehicle, wheel columns ordered fl, fr, rl, rr) and free of MuJoCo:
the world reads loads and friction from the model, calls :meth:`update`, and
writes the outputs back.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from osc2runner.sim.vehicle import VehicleParams

__all__ = ["ActuatorBank"]


def _col(values: Sequence[float]) -> np.ndarray:
    return np.asarray(values, dtype=float)


class ActuatorBank:
    """Rate limits, drive/brake torques, ABS/TCS and Ackermann for N vehicles.

    Parameters:
        params: one parameter set per vehicle, in world order.
        dt: control period in seconds (the rate limits apply per call).
    """

    def __init__(self, params: Sequence[VehicleParams], dt: float) -> None:
        self.dt = float(dt)
        self.count = n = len(params)
        self.max_steer = _col([p.max_steer for p in params])
        self.steer_rate = _col([p.steer_rate for p in params])
        self.throttle_rate = _col([p.throttle_rate for p in params])
        self.brake_rate = _col([p.brake_rate for p in params])
        self.wheelbase = _col([p.wheelbase for p in params])
        self.half_track = _col([0.5 * p.track for p in params])
        self.radius = _col([p.wheel_radius for p in params])
        self.max_force = _col([p.max_drive_force for p in params])
        self.max_power = _col([p.max_power for p in params])
        self.drag = _col([0.5 * p.air_density * p.drag_area for p in params])
        self.driven = np.array([p.driven for p in params], dtype=bool).reshape(n, 4)
        self.n_driven = self.driven.sum(axis=1).astype(float)
        self.brake_max = np.array([p.brake_torque_per_wheel for p in params]).reshape(n, 4)
        self.static_load = np.array([p.static_wheel_loads for p in params]).reshape(n, 4)
        mass = _col([p.mass for p in params])
        h_over_l = _col([p.h_cog / p.wheelbase for p in params])
        # load transfer per m/s² of acceleration: longitudinal per wheel, lateral per wheel
        self.transfer_x = 0.5 * mass * h_over_l
        front_share = _col([p.lr / p.wheelbase for p in params])
        h_over_t = _col([p.h_cog / p.track for p in params])
        self.transfer_y = (mass * h_over_t)[:, None] * np.stack(
            (front_share, front_share, 1.0 - front_share, 1.0 - front_share), axis=1
        )
        # the same with their signs per wheel (multiplying by -1 or 1 is exact, so the
        # loads are those of applying the signs after the acceleration)
        self._transfer_along = self.transfer_x[:, None] * _ALONG
        self._transfer_across = self.transfer_y * _ACROSS
        self.rolling_torque = (
            _col([p.rolling_resistance for p in params])[:, None]
            * self.static_load
            * self.radius[:, None]
        )
        # torque caps per newton of friction budget (inf when ABS / TCS are off)
        abs_margin = [p.abs_margin if p.abs_enabled else math.inf for p in params]
        tcs_margin = [p.tcs_margin if p.tcs_enabled else math.inf for p in params]
        self.abs_cap = (_col(abs_margin) * self.radius)[:, None]
        self.tcs_cap = (_col(tcs_margin) * self.radius)[:, None]

        # commands (after clipping) and applied, rate-limited values: rows (throttle,
        # brake, steer) of one array each, so the three rate limiters are one expression
        # per tick (numpy's cost is per call on arrays of a few vehicles)
        self._command = np.zeros((3, n))
        self._applied = np.zeros((3, n))  # throttle, brake, road-wheel angle (rad)
        self.cmd_throttle, self.cmd_brake, self.cmd_steer = self._command
        self.throttle, self.brake, self.delta = self._applied
        self._command_scale = np.stack((np.ones(n), np.ones(n), self.max_steer))
        self._rate_step = np.stack((self.throttle_rate, self.brake_rate, self.steer_rate)) * self.dt
        self._rate_floor = -self._rate_step

        # outputs of the last update
        self.drive_torque = np.zeros((n, 4))
        self.brake_torque = np.zeros((n, 4))  # incl. rolling resistance
        self.steer_angles = np.zeros((n, 2))  # left, right road-wheel angles
        self.drag_coefficient = self.drag  # force = -drag * |v| * v

    # ------------------------------------------------------------------ inputs

    def set_command(self, index: int, throttle: float, brake: float, steer: float) -> None:
        """Store the driver inputs of vehicle ``index``, clipped to their ranges."""
        self.cmd_throttle[index] = min(max(throttle, 0.0), 1.0)
        self.cmd_brake[index] = min(max(brake, 0.0), 1.0)
        self.cmd_steer[index] = min(max(steer, -1.0), 1.0)

    def reset(self, index: int | None = None) -> None:
        """Zero commands and applied values (all vehicles, or one)."""
        sel = slice(None) if index is None else index
        self._command[:, sel] = 0.0
        self._applied[:, sel] = 0.0

    @property
    def steer(self) -> np.ndarray:
        """Applied steering as a fraction of the maximum road-wheel angle."""
        steer: np.ndarray = self.delta / self.max_steer
        return steer

    # ------------------------------------------------------------------ update

    def estimate_loads(self, accel: np.ndarray, lat_accel: np.ndarray) -> np.ndarray:
        """Wheel loads (N) from static loads plus load transfer, shape (n, 4).

        The ECU works with this estimate rather than the contact forces of
        the last physics step: those are a single 2 ms sample and jump
        whenever a tire skips (reference/vehicle-model.md §4.1, "model loads"
        were also the smoother variant there).
        """
        # front wheels unload when accelerating; left wheels unload in a left turn (the
        # signs are exact: multiplying by -1 and adding is subtracting)
        load = self.static_load + self._transfer_along * accel[:, None]
        load += self._transfer_across * lat_accel[:, None]
        loads: np.ndarray = np.maximum(load, 0.0, out=load)
        return loads

    def update(
        self, speed: np.ndarray, mu: np.ndarray, accel: np.ndarray, lat_accel: np.ndarray
    ) -> None:
        """Advance the rate limiters by one tick and compute the outputs.

        Parameters:
            speed: longitudinal speed of each vehicle (m/s), shape (n,).
            mu: tire friction coefficient per wheel, shape (n, 4).
            accel: longitudinal acceleration over the last tick (m/s²), shape (n,).
            lat_accel: lateral acceleration (m/s², positive to the left), shape (n,).
        """
        load = self.estimate_loads(accel, lat_accel)
        # rate limits: the change towards each command, clipped to one tick's step
        change = self._command * self._command_scale
        change -= self._applied
        np.maximum(change, self._rate_floor, out=change)
        np.minimum(change, self._rate_step, out=change)
        self._applied += change

        grip = mu * load  # friction force budget per wheel

        force = np.minimum(self.max_force, self.max_power / np.maximum(np.abs(speed), 1.0))
        per_wheel = (self.throttle * force * self.radius / self.n_driven)[:, None]
        drive = np.where(self.driven, per_wheel, 0.0)
        np.minimum(drive, self.tcs_cap * grip, out=drive)
        self.drive_torque = drive

        brake = self.brake[:, None] * self.brake_max
        np.minimum(brake, self.abs_cap * grip, out=brake)
        self.brake_torque = brake + self.rolling_torque

        # Ackermann: inner wheel steers more; tan(d_side) = L tan d / (L -/+ T/2 tan d)
        tan_d = np.tan(self.delta)
        lw = self.wheelbase
        along, across = lw * tan_d, self.half_track * tan_d
        np.arctan2(along, lw - across, out=self.steer_angles[:, 0])
        np.arctan2(along, lw + across, out=self.steer_angles[:, 1])


_ALONG = np.array([-1.0, -1.0, 1.0, 1.0])  # per wheel FL, FR, RL, RR
_ACROSS = np.array([-1.0, 1.0, -1.0, 1.0])
