"""The walkers (pedestrians) of one world: kinematic bodies moved along their commanded velocity.

A walker is a MuJoCo ``mocap`` body: the world does not simulate it, it moves it
each control step by its commanded velocity. :class:`WalkerBank` owns their
inputs, poses and read-out. A walker that stands still (no speed, no acceleration)
keeps its pose and its state: nothing is moved, read, or checked for it until it
moves again, so idle walkers cost nothing per tick.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np

from osc2check.world.tracking import RoadPosition
from osc2runner.sim.bank import Bank, element_id
from osc2runner.sim.mjcf import yaw_quat
from osc2runner.sim.state import ActorSpec, ActorState, PedestrianInput, actor_state

__all__ = ["WalkerBank"]


class WalkerBank(Bank):
    """The walkers of one world, in world order.

    Parameters:
        model, data: the compiled MuJoCo model and its data.
        specs: the walkers' specs.
        prefixes: each walker's body name in the model.
        index: each walker's position among all the world's actors.
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
        super().__init__(specs, index)
        self.data = data
        self.dt = dt
        self.mocap = np.array(
            [model.body_mocapid[element_id(model, mujoco.mjtObj.mjOBJ_BODY, p)] for p in prefixes],
            dtype=int,
        )
        self.reset()

    def reset(self) -> None:
        """No input, no motion, nothing travelled; every walker counted as moving until
        it is placed (placing says whether it stands still)."""
        n = self.count
        self.vel = np.zeros((n, 3))
        self.speed = np.zeros(n)
        self.yaw = np.zeros(n)
        self.accel = np.zeros(n)
        self.distance = np.zeros(n)
        self.input: list[PedestrianInput | None] = [None] * n
        self.still = [False] * n
        self.moving = n  # how many walkers move
        self.kept: list[ActorState | None] = [None] * n  # the state of a walker standing still
        self.all_kept = False  # every walker stands still and has its state kept
        self.dirty = True  # a walker's pose changed: its row of the world's pose arrays too
        self.unchecked = True  # ... and its position is not known to be finite

    # ------------------------------------------------------------------ inputs

    def place(self, row: int, x: float, y: float, yaw: float, speed: float) -> bool:
        """Put walker ``row`` at ``(x, y)`` walking at ``speed`` along ``yaw``; returns
        whether it changed from standing still to moving or back."""
        d = self.data
        mid = self.mocap[row]
        d.mocap_pos[mid, :2] = (x, y)
        d.mocap_quat[mid] = yaw_quat(yaw)
        self.speed[row] = speed
        self.yaw[row] = yaw
        self.vel[row] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0)
        self.input[row] = None
        return self._moves(row, speed != 0.0 or self.accel[row] != 0.0)

    def set_input(self, row: int, value: PedestrianInput) -> bool:
        """The velocity walker ``row`` holds from the next control step on; returns
        whether it changed from standing still to moving or back."""
        held = self.input[row]
        if (held is value or held == value) and self.accel[row] == 0.0:
            return False  # the same input as held: nothing changes (idle walkers cost nothing)
        self.input[row] = value
        yaw = value.yaw
        speed = value.speed
        self.vel[row] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0)
        self.yaw[row] = yaw
        self.accel[row] = (speed - self.speed[row]) / self.dt
        self.speed[row] = speed
        self.data.mocap_quat[self.mocap[row]] = yaw_quat(yaw)
        return self._moves(row, speed != 0.0 or self.accel[row] != 0.0)

    def _moves(self, row: int, moves: bool) -> bool:
        self.kept[row] = None
        self.all_kept = False
        self.dirty = self.unchecked = True
        if self.still[row] != moves:
            return False
        self.still[row] = not moves
        self.moving += 1 if moves else -1
        return True

    def still_index(self) -> set[int]:
        """The world positions of the walkers that stand still."""
        return {int(self.index[row]) for row, still in enumerate(self.still) if still}

    def move(self) -> None:
        """Move the walkers that move by their velocity over one control step."""
        if self.moving:
            self.data.mocap_pos[self.mocap] += self.vel * self.dt

    # ------------------------------------------------------------------ read-out

    def read_step(self) -> None:
        """After a control step: the distance travelled."""
        if self.moving:
            self.distance += np.abs(self.speed) * self.dt

    def poses(self, centre: np.ndarray, yaw: np.ndarray) -> None:
        """Write the walkers' positions and headings into the world's pose arrays (only
        when one of them moved)."""
        if self.moving or self.dirty:
            centre[self.index] = self.data.mocap_pos[self.mocap, :2]
            yaw[self.index] = self.yaw
            self.dirty = False

    def state(self, row: int, tick: int, time: float, where: RoadPosition) -> ActorState:
        """The state of walker ``row``, ``where`` on the map."""
        pos = self.data.mocap_pos[self.mocap[row]]
        return self._state(
            row, tick, time, float(pos[0]), float(pos[1]), float(self.yaw[row]),
            float(self.speed[row]), float(self.accel[row]), where,
        )  # fmt: skip

    def _state(
        self,
        row: int,
        tick: int,
        time: float,
        x: float,
        y: float,
        yaw: float,
        speed: float,
        accel: float,
        where: RoadPosition,
    ) -> ActorState:
        params = self.specs[row].params
        nan = math.nan
        return actor_state(
            self.names[row], "pedestrian", tick, time, x, y, yaw, speed, 0.0, 0.0, accel,
            nan, nan, nan, nan, params.length, params.width, where,
            float(self.distance[row]),
        )  # fmt: skip

    def read_states(
        self, out: dict[str, ActorState], tick: int, time: float, positions: Sequence[RoadPosition]
    ) -> None:
        """Write every walker's state into ``out`` (the same values as :meth:`state`); a
        walker that stands still keeps its state, whose ``tick`` and ``time`` are those of
        when it stopped (as an obstacle's are those of the start)."""
        if not self.count:
            return
        still, kept = self.still, self.kept
        if self.all_kept:
            for name, state in zip(self.names, kept, strict=True):
                out[name] = state  # type: ignore[assignment]
            return
        pos = self.data.mocap_pos[self.mocap, :2].tolist()
        speed = self.speed.tolist()
        yaw = self.yaw.tolist()
        accel = self.accel.tolist()
        index = self.index.tolist()
        for row, name in enumerate(self.names):
            if still[row] and kept[row] is not None:
                out[name] = kept[row]  # type: ignore[assignment]
                continue
            x, y = pos[row]
            where = positions[index[row]]
            state = out[name] = self._state(
                row, tick, time, x, y, yaw[row], speed[row], accel[row], where
            )
            if still[row]:
                kept[row] = state
        self.all_kept = not self.moving

    def non_finite(self) -> tuple[str, str] | None:
        """``(name, what)`` of the first walker whose position or speed is not finite
        (only walkers that moved since the last check are looked at)."""
        d = self.data
        if (self.moving or self.unchecked) and not np.isfinite(d.mocap_pos[self.mocap]).all():
            for row, name in enumerate(self.names):
                x, y = d.mocap_pos[self.mocap[row], :2].tolist()
                speed = float(self.speed[row])
                if not all(math.isfinite(v) for v in (x, y, speed)):
                    return name, f"non-finite state: x {x}, y {y}, speed {speed}"
        self.unchecked = False
        return None
