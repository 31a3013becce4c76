"""Where every actor is on the map: road coordinates from world poses, each tick.

:class:`ActorLocators` keeps one :class:`~osc2check.world.tracking.RoadLocator`
per actor (it prefers the path the actor's driver follows, and where it was) and
the last :class:`~osc2check.world.tracking.RoadPosition` found for each; an actor
whose position did not change since it was last located is not located again.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from osc2check.world.network import RoadNetwork
from osc2check.world.paths import LanePath
from osc2check.world.tracking import RoadLocator, RoadPosition

__all__ = ["ActorLocators"]


class ActorLocators:
    """The road positions of a world's actors, in world order, from their initial ``poses``."""

    def __init__(self, network: RoadNetwork, poses: Sequence[tuple[float, float, float]]) -> None:
        self._locators = [RoadLocator(network) for _ in poses]
        self.positions: list[RoadPosition] = [
            loc.locate(*pose) for loc, pose in zip(self._locators, poses, strict=True)
        ]
        self._located: list[tuple[float, float] | None] = [None] * len(poses)

    def forget(self, i: int | None = None) -> None:
        """Forget where actor ``i`` (or every actor) was: it was moved, not driven there."""
        if i is None:
            self._located = [None] * len(self._located)
            return
        self._locators[i].reset()
        self._located[i] = None

    def follow(self, i: int, path: LanePath | None) -> None:
        """Take actor ``i``'s road coordinates on ``path`` where roads overlap."""
        self._locators[i].follow(path)

    def locate(self, rows: Iterable[int], centre: np.ndarray, yaw: np.ndarray) -> None:
        """Locate the actors ``rows`` at their ``centre`` (n, 2) and ``yaw`` (n,)."""
        points = centre.tolist()
        angles = yaw.tolist()
        positions, locators, last = self.positions, self._locators, self._located
        for i in rows:
            x, y = points[i]
            if last[i] == (x, y):
                continue  # a walker standing still: where it was
            last[i] = (x, y)
            positions[i] = locators[i].locate(x, y, angles[i])
