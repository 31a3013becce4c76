"""The obstacles of one world: static boxes that stand where they were put."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from osc2check.world.tracking import RoadPosition
from osc2runner.sim.bank import Bank
from osc2runner.sim.state import ActorSpec, ActorState, actor_state

__all__ = ["ObstacleBank"]


class ObstacleBank(Bank):
    """The obstacles of one world, in world order.

    Parameters:
        specs: the obstacles' specs.
        poses: each obstacle's world ``(x, y, yaw)``.
        index: each obstacle's position among all the world's actors.
    """

    def __init__(
        self,
        specs: Sequence[ActorSpec],
        poses: Sequence[tuple[float, float, float]],
        index: Sequence[int],
    ) -> None:
        super().__init__(specs, index)
        self.initial = tuple(poses)
        self.pose = np.array(poses, dtype=float).reshape(-1, 3)

    def poses(self, centre: np.ndarray, yaw: np.ndarray) -> None:
        """Write the obstacles' positions and headings into the world's pose arrays."""
        if self.count:
            centre[self.index] = self.pose[:, :2]
            yaw[self.index] = self.pose[:, 2]

    def state(self, row: int, tick: int, time: float, where: RoadPosition) -> ActorState:
        """The state of obstacle ``row``, ``where`` on the map."""
        x, y, yaw = self.initial[row]
        params = self.specs[row].params
        nan = math.nan
        return actor_state(
            self.names[row], "obstacle", tick, time, x, y, yaw, 0.0, 0.0, 0.0, 0.0,
            nan, nan, nan, nan, params.length, params.width, where, 0.0,
        )  # fmt: skip

    def read_states(
        self, out: dict[str, ActorState], tick: int, time: float, positions: Sequence[RoadPosition]
    ) -> None:
        """Write every obstacle's state into ``out``."""
        for row, i in enumerate(self.index.tolist()):
            out[self.names[row]] = self.state(row, tick, time, positions[i])
