"""The vehicles of one world: their model indices, inputs and read-out, vectorised.

:class:`VehicleBank` owns what the world knows of its vehicles: where each one's
bodies, joints, tires and actuators are in the MuJoCo model, the actuator layer
(``sim/actuators.py``) that turns driver inputs into torques and steering angles,
each tire's friction, and the read-out of the last step (pose, velocities,
acceleration, distance travelled), from which it makes their
:class:`~osc2runner.sim.state.ActorState`. What it shares with the kinematic
vehicles (``sim/kinematic_bank.py``: the inputs, the friction, the states made from
the read-out) is :class:`DrivenBank`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial

import mujoco
import numpy as np

from osc2check.world.tracking import RoadPosition
from osc2runner.sim.actuators import ActuatorBank
from osc2runner.sim.bank import Bank, element_id
from osc2runner.sim.free_body import drag_forces, free_body_state, set_free_body
from osc2runner.sim.state import ActorSpec, ActorState, actor_state
from osc2runner.sim.vehicle import WHEELS, VehicleParams

__all__ = ["DrivenBank", "VehicleBank", "four"]


def four(values: np.ndarray) -> tuple[float, float, float, float]:
    """A per-wheel row (fl, fr, rl, rr) as a tuple of floats."""
    a, b, c, d = (float(v) for v in values)
    return (a, b, c, d)


class DrivenBank(Bank):
    """Vehicles driven through the actuator layer, whatever moves them: their parameters,
    inputs, tires' friction, and the states made from their read-out (``pos``, ``yaw``,
    ``speed``, ``lat_speed``, ``yaw_rate``, ``accel``, ``distance``, set by the subclass).
    """

    pos: np.ndarray
    yaw: np.ndarray
    speed: np.ndarray
    lat_speed: np.ndarray
    yaw_rate: np.ndarray

    def __init__(self, specs: Sequence[ActorSpec], index: Sequence[int], dt: float) -> None:
        super().__init__(specs, index)
        self.params = tuple(p for s in specs if isinstance(p := s.params, VehicleParams))
        self.dt = dt
        n = self.count
        self.actuators = ActuatorBank(self.params, dt)
        self.mu = np.ones((n, 4))  # each tire's friction
        self.mu_mean = [1.0] * n
        self.accel = np.zeros(n)
        self.distance = np.zeros(n)

    def reset(self) -> None:
        """No input applied, nothing travelled."""
        self.actuators.reset()
        self.accel = np.zeros(self.count)
        self.distance = np.zeros(self.count)

    def set_input(self, row: int, throttle: float, brake: float, steer: float) -> None:
        """The driver inputs vehicle ``row`` holds from the next control step on."""
        self.actuators.set_command(row, throttle, brake, steer)

    def set_friction(self, mu: float, row: int | None = None, wheel: int | None = None) -> None:
        """Set the friction of every tire, of vehicle ``row``'s, or of one of its wheels
        (in effect from :meth:`write_friction` on)."""
        if row is None:
            self.mu[:] = mu
        elif wheel is None:
            self.mu[row] = mu
        else:
            self.mu[row, wheel] = mu

    def write_friction(self) -> None:
        """Put the per-tire friction in effect (from the next step on)."""
        self.mu_mean = [float(v) for v in self.mu.mean(axis=1)]

    def state(self, row: int, tick: int, time: float, where: RoadPosition) -> ActorState:
        """The state of vehicle ``row``, ``where`` on the map."""
        bank = self.actuators
        params = self.params[row]
        return actor_state(
            self.names[row],
            "vehicle",
            tick,
            time,
            float(self.pos[row, 0]),
            float(self.pos[row, 1]),
            float(self.yaw[row]),
            float(self.speed[row]),
            float(self.lat_speed[row]),
            float(self.yaw_rate[row]),
            float(self.accel[row]),
            self.mu_mean[row],
            float(bank.throttle[row]),
            float(bank.brake[row]),
            float(bank.delta[row] / bank.max_steer[row]),
            params.length,
            params.width,
            where,
            float(self.distance[row]),
        )

    def read_states(
        self, out: dict[str, ActorState], tick: int, time: float, positions: Sequence[RoadPosition]
    ) -> None:
        """Write every vehicle's state into ``out`` in one pass over the arrays (the same
        values as :meth:`state`); ``positions`` are every actor's, in world order."""
        if not self.count:
            return
        bank = self.actuators
        pos = self.pos.tolist()
        yaw = self.yaw.tolist()
        speed = self.speed.tolist()
        lat = self.lat_speed.tolist()
        yaw_rate = self.yaw_rate.tolist()
        accel = self.accel.tolist()
        throttle = bank.throttle.tolist()
        brake = bank.brake.tolist()
        steer = (bank.delta / bank.max_steer).tolist()
        distance = self.distance.tolist()
        mu = self.mu_mean
        index = self.index.tolist()
        for row, (name, params) in enumerate(zip(self.names, self.params, strict=True)):
            x, y = pos[row]
            out[name] = actor_state(
                name,
                "vehicle",
                tick,
                time,
                x,
                y,
                yaw[row],
                speed[row],
                lat[row],
                yaw_rate[row],
                accel[row],
                mu[row],
                throttle[row],
                brake[row],
                steer[row],
                params.length,
                params.width,
                positions[index[row]],
                distance[row],
            )

    def non_finite(self) -> tuple[str, str] | None:
        """``(name, what)`` of the first vehicle whose position or speed is not finite."""
        if not self.count or math.isfinite(
            float(self.speed.dot(self.speed)) + float(np.vdot(self.pos, self.pos))
        ):
            return None
        for row, name in enumerate(self.names):
            (x, y), speed = self.pos[row].tolist(), float(self.speed[row])
            if not all(math.isfinite(v) for v in (x, y, speed)):
                return name, f"non-finite state: x {x}, y {y}, speed {speed}"
        return None


class VehicleBank(DrivenBank):
    """The vehicles of one world that the physics model moves, in world order.

    Parameters:
        model, data: the compiled MuJoCo model and its data.
        specs: the vehicles' specs.
        prefixes: each vehicle's body name in the model.
        index: each vehicle's position among all the world's actors.
        dt: the control period (s).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        specs: Sequence[ActorSpec],
        prefixes: Sequence[str],
        index: Sequence[int],
        dt: float,
    ) -> None:
        super().__init__(specs, index, dt)
        self.model, self.data = model, data
        n = self.count

        jid = partial(element_id, model, mujoco.mjtObj.mjOBJ_JOINT)
        aid = partial(element_id, model, mujoco.mjtObj.mjOBJ_ACTUATOR)
        gid = partial(element_id, model, mujoco.mjtObj.mjOBJ_GEOM)
        bid = partial(element_id, model, mujoco.mjtObj.mjOBJ_BODY)

        self.body = np.zeros(n, dtype=int)
        self.qadr = np.zeros(n, dtype=int)
        self.vadr = np.zeros(n, dtype=int)
        self.spin_dof = np.zeros((n, 4), dtype=int)
        self.wheel_body = np.zeros((n, 4), dtype=int)
        self.tire = np.zeros((n, 4), dtype=int)
        self.steer_act = np.zeros((n, 2), dtype=int)
        drive_act: list[int] = []
        #: per geom: 4 * row + wheel of the tire it is, -1 for every other geom
        self.geom_wheel = np.full(model.ngeom, -1, dtype=int)
        for row, prefix in enumerate(prefixes):
            root = jid(f"{prefix}_root")
            self.body[row] = bid(prefix)
            self.qadr[row] = model.jnt_qposadr[root]
            self.vadr[row] = model.jnt_dofadr[root]
            for w, wheel in enumerate(WHEELS):
                name = f"{prefix}_{wheel}"
                self.spin_dof[row, w] = model.jnt_dofadr[jid(f"{name}_spin")]
                self.wheel_body[row, w] = bid(f"{name}_wheel")
                self.tire[row, w] = gid(f"{name}_tire")
                self.geom_wheel[self.tire[row, w]] = 4 * row + w
                if self.params[row].driven[w]:
                    drive_act.append(aid(f"{name}_drive"))
            self.steer_act[row] = (aid(f"{prefix}_fl_steer"), aid(f"{prefix}_fr_steer"))
        self.drive_act = np.asarray(drive_act, dtype=int)
        self.driven_mask = np.array([p.driven for p in self.params], dtype=bool).reshape(n, 4)
        self._q7 = self.qadr[:, None] + np.arange(7)
        self._v6 = self.vadr[:, None] + np.arange(6)
        self.read()

    def hold_still(self) -> None:
        """Full brakes on every wheel (for settling the suspensions at rest)."""
        self.model.dof_frictionloss[self.spin_dof.ravel()] = self.actuators.brake_max.ravel()

    # ------------------------------------------------------------------ inputs

    def apply(self) -> None:
        """Run the actuator layer on this tick's inputs and write torques, steering
        angles and drag into the model."""
        m, d, bank = self.model, self.data, self.actuators
        bank.update(self.speed, self.mu, self.accel, self.speed * self.yaw_rate)
        d.ctrl[self.drive_act] = bank.drive_torque[self.driven_mask]
        m.dof_frictionloss[self.spin_dof] = bank.brake_torque
        d.ctrl[self.steer_act] = bank.steer_angles
        d.xfrc_applied[self.body, :2] = drag_forces(bank.drag_coefficient, self.vel)

    def place(self, row: int, x: float, y: float, yaw: float, speed: float) -> None:
        """Move vehicle ``row`` to ``(x, y)`` heading ``yaw`` at ``speed`` (see
        :func:`~osc2runner.sim.free_body.set_free_body`)."""
        set_free_body(
            self.model, self.data, self.qadr[row], self.vadr[row], self.spin_dof[row],
            self.wheel_body[row], x, y, yaw, speed,
        )  # fmt: skip
        self.read()
        self.accel[row] = 0.0

    # ------------------------------------------------------------------ friction

    def write_friction(self) -> None:
        """Copy the per-tire friction into the model (effective at the next step)."""
        self.model.geom_friction[self.tire, 0] = self.mu
        super().write_friction()

    # ------------------------------------------------------------------ read-out

    def read(self) -> None:
        """Read every vehicle's pose and velocities from the model."""
        if self.count:
            (
                self.pos,
                self.yaw,
                self.vel,
                self.yaw_rate,
                self.cos,
                self.sin,
                self.speed,
                self.lat_speed,
            ) = free_body_state(self.data.qpos[self._q7], self.data.qvel[self._v6])
        else:
            self.pos = np.zeros((0, 2))
            self.yaw = self.speed = self.lat_speed = self.yaw_rate = np.zeros(0)
            self.vel = np.zeros((0, 3))

    def read_step(self) -> None:
        """Read after a control step: the new state, the acceleration over the step along
        the new heading and the distance travelled."""
        prev = self.vel
        self.read()
        if self.count:
            dv = (self.vel - prev) / self.dt
            self.accel = dv[:, 0] * self.cos + dv[:, 1] * self.sin
            self.distance += np.abs(self.speed) * self.dt

    def wheel_loads(self, row: int) -> tuple[float, float, float, float]:
        """Normal load (N) of each tire of vehicle ``row`` from the last step's contacts."""
        d, n = self.data, self.count
        if d.ncon == 0:
            return (0.0, 0.0, 0.0, 0.0)
        contact = d.contact
        wheel = self.geom_wheel[contact.geom].max(axis=1)
        adr = contact.efc_address
        ok = (wheel >= 0) & (adr >= 0)
        force = d.efc_force[adr[ok]]  # elliptic cones: the first row is the normal force
        loads = np.bincount(wheel[ok], weights=force, minlength=4 * n).reshape(n, 4)
        return four(loads[row])

    def wheel_speeds(self, row: int) -> tuple[float, float, float, float]:
        """Spin rate times radius (m/s) of each wheel of vehicle ``row``."""
        return four(self.data.qvel[self.spin_dof[row]] * self.actuators.radius[row])
