"""The trailers of one world: their model indices, brakes, drag and read-out, vectorised.

:class:`TrailerBank` owns what the world knows of its trailers (``sim/trailer.py``
has their parameters and bodies): where each one's body, joints and tires are in
the model, which vehicle tows it, its tires' friction, and the read-out of the last
step, from which it makes their :class:`~osc2runner.sim.state.ActorState`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial

import mujoco
import numpy as np

from osc2check.world.tracking import RoadPosition
from osc2runner.sim.bank import Bank, element_id
from osc2runner.sim.free_body import drag_forces, free_body_state, set_free_body
from osc2runner.sim.state import ActorSpec, ActorState, actor_state
from osc2runner.sim.trailer import TRAILER_WHEELS, TrailerParams, articulation

__all__ = ["TrailerBank"]


class TrailerBank(Bank):
    """The trailers of one world, in world order.

    Parameters:
        model, data: the compiled MuJoCo model and its data.
        specs: the trailers' specs.
        prefixes: each trailer's body name in the model.
        index: each trailer's position among all the world's actors.
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
        jid = partial(element_id, model, mujoco.mjtObj.mjOBJ_JOINT)
        bid = partial(element_id, model, mujoco.mjtObj.mjOBJ_BODY)
        gid = partial(element_id, model, mujoco.mjtObj.mjOBJ_GEOM)
        super().__init__(specs, index)
        self.model, self.data = model, data
        params = self.params = tuple(p for s in specs if isinstance(p := s.params, TrailerParams))
        self.dt = dt
        n = self.count
        self.body = np.array([bid(p) for p in prefixes], dtype=int)
        root = [jid(f"{p}_root") for p in prefixes]
        self.qadr = np.array([model.jnt_qposadr[j] for j in root], dtype=int)
        self.vadr = np.array([model.jnt_dofadr[j] for j in root], dtype=int)
        self.spin_dof = np.array(
            [[model.jnt_dofadr[jid(f"{p}_{w}_spin")] for w in TRAILER_WHEELS] for p in prefixes],
            dtype=int,
        ).reshape(n, 2)
        self.wheel_body = np.array(
            [[bid(f"{p}_{w}_wheel") for w in TRAILER_WHEELS] for p in prefixes],
            dtype=int,
        ).reshape(n, 2)
        self.tire = np.array(
            [[gid(f"{p}_{w}_tire") for w in TRAILER_WHEELS] for p in prefixes],
            dtype=int,
        ).reshape(n, 2)
        radius = np.array([p.wheel_radius for p in params])
        self.radius = radius
        self.brake_max = np.repeat(
            np.array([0.5 * p.max_brake_torque for p in params])[:, None], 2, axis=1
        )
        load = np.array([p.static_wheel_load for p in params])
        self.static_load = np.repeat(load[:, None], 2, axis=1)
        self.rolling_torque = (
            np.array([p.rolling_resistance for p in params])[:, None]
            * self.static_load
            * radius[:, None]
        )
        self.abs_cap = (np.array([p.abs_margin for p in params]) * radius)[:, None]
        self.drag = np.array([0.5 * p.air_density * p.drag_area for p in params])
        self._q7 = self.qadr[:, None] + np.arange(7)
        self._v6 = self.vadr[:, None] + np.arange(6)
        self.mu = np.ones((n, 2))  # each tire's friction
        #: per trailer: the row of the vehicle that tows it (in the vehicle bank), or None
        self.tow_row: list[int | None] = [None] * n
        self.reset()

    def reset(self) -> None:
        """No brake applied, hitched to nothing, nothing read or travelled yet."""
        n = self.count
        self.brake = np.zeros(n)  # applied brake, fraction of the maximum
        self.pos = np.zeros((n, 2))
        self.yaw = np.zeros(n)
        self.vel = np.zeros((n, 3))
        self.speed = np.zeros(n)
        self.lat_speed = np.zeros(n)
        self.yaw_rate = np.zeros(n)
        self.accel = np.zeros(n)
        self.distance = np.zeros(n)
        self.tow_row = [None] * n

    def hold_still(self) -> None:
        """Brakes on every wheel (for settling the suspensions at rest)."""
        self.model.dof_frictionloss[self.spin_dof.ravel()] = np.repeat(
            [p.mass * p.wheel_radius * 5.0 for p in self.params], 2
        )

    # ------------------------------------------------------------------ inputs

    def apply(self, tow_brake: np.ndarray) -> None:
        """Write this tick's brake torques and drag into the model: a hitched trailer brakes
        as its tow vehicle does (``tow_brake``: the vehicles' applied brake), an unhitched
        one is parked; each wheel ABS-capped with its friction."""
        for row, tow in enumerate(self.tow_row):
            self.brake[row] = tow_brake[tow] if tow is not None else 1.0
        brake = self.brake[:, None] * self.brake_max
        np.minimum(brake, self.abs_cap * self.mu * self.static_load, out=brake)
        self.model.dof_frictionloss[self.spin_dof] = brake + self.rolling_torque
        self.data.xfrc_applied[self.body, :2] = drag_forces(self.drag, self.vel)

    def place(self, row: int, x: float, y: float, yaw: float, speed: float) -> None:
        """Move trailer ``row`` to ``(x, y)`` heading ``yaw`` at ``speed``."""
        set_free_body(
            self.model, self.data, self.qadr[row], self.vadr[row], self.spin_dof[row],
            self.wheel_body[row], x, y, yaw, speed,
        )  # fmt: skip
        self.read()
        self.accel[row] = 0.0

    def write_friction(self) -> None:
        """Copy the per-tire friction into the model (effective at the next step)."""
        self.model.geom_friction[self.tire, 0] = self.mu

    # ------------------------------------------------------------------ read-out

    def read(self, dt: float | None = None) -> None:
        """Read every trailer's pose and velocity; with ``dt``, its acceleration over it."""
        q = self.data.qpos[self._q7]
        v = self.data.qvel[self._v6]
        prev = self.vel
        self.pos, self.yaw, self.vel, self.yaw_rate, c, s, self.speed, self.lat_speed = (
            free_body_state(q, v)
        )
        if dt is not None:
            dv = (self.vel - prev) / dt
            self.accel = dv[:, 0] * c + dv[:, 1] * s

    def read_step(self) -> None:
        """Read after a control step: the new state, the acceleration over the step and
        the distance travelled."""
        self.read(self.dt)
        self.distance += np.abs(self.speed) * self.dt

    def articulation(self, row: int, tow_yaw: np.ndarray) -> float:
        """Trailer ``row``'s articulation angle (NaN when it is not hitched), its tow
        vehicle's heading read from ``tow_yaw`` (the vehicles' yaw)."""
        tow = self.tow_row[row]
        if tow is None:
            return math.nan
        return articulation(float(tow_yaw[tow]), float(self.yaw[row]))

    def state(
        self, row: int, tick: int, time: float, where: RoadPosition, tow_yaw: np.ndarray
    ) -> ActorState:
        """The state of trailer ``row``, ``where`` on the map."""
        x, y = (float(v) for v in self.pos[row])
        params = self.params[row]
        return actor_state(
            self.names[row],
            "trailer",
            tick,
            time,
            x,
            y,
            float(self.yaw[row]),
            float(self.speed[row]),
            float(self.lat_speed[row]),
            float(self.yaw_rate[row]),
            float(self.accel[row]),
            float(self.mu[row].mean()),
            math.nan,
            float(self.brake[row]) if params.braked else 0.0,
            math.nan,
            params.length,
            params.width,
            where,
            float(self.distance[row]),
            self.articulation(row, tow_yaw),
        )

    def read_states(
        self,
        out: dict[str, ActorState],
        tick: int,
        time: float,
        positions: Sequence[RoadPosition],
        tow_yaw: np.ndarray,
    ) -> None:
        """Write every trailer's state into ``out``; ``positions`` are every actor's."""
        for row, (name, i) in enumerate(zip(self.names, self.index.tolist(), strict=True)):
            out[name] = self.state(row, tick, time, positions[i], tow_yaw)

    def non_finite(self) -> tuple[str, str] | None:
        """``(name, what)`` of the first trailer whose position or speed is not finite."""
        for row, name in enumerate(self.names):
            (x, y), speed = self.pos[row].tolist(), float(self.speed[row])
            if not all(math.isfinite(v) for v in (x, y, speed)):
                return name, f"non-finite state: x {x}, y {y}, speed {speed}"
        return None
