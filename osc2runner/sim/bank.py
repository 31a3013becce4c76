"""What every bank of bodies (vehicles, trailers, walkers, obstacles) has: its actors'
specs and names in world order, the row of each name, and each row's position among all
the world's actors; and the lookup of a named MuJoCo element."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from osc2runner.sim.state import ActorSpec

__all__ = ["Bank", "element_id"]


class Bank:
    """The actors of one body kind, in world order (``index``: each one's position among
    all the world's actors)."""

    def __init__(self, specs: Sequence[ActorSpec], index: Sequence[int]) -> None:
        self.specs = tuple(specs)
        self.names = tuple(spec.name for spec in specs)
        self.rows = {name: row for row, name in enumerate(self.names)}
        self.index = np.array(index, dtype=int)
        self.count = len(self.specs)


def element_id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    """The id of the model's element ``name`` of ``kind`` (a joint, body, geom, ...)."""
    return int(mujoco.mj_name2id(model, kind, name))
