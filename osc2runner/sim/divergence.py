"""MuJoCo's own reports of a diverged simulation, named by the actor concerned.

When the physics finds NaN, infinite or huge values in ``qpos``, ``qvel`` or
``qacc``, MuJoCo warns and resets its state to the initial one, so the state
afterwards looks finite but is teleported. :class:`DivergenceWatch` counts those
warnings and, when their count grows, names the actor whose body the warning
points at.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

__all__ = ["DivergenceWatch"]

#: MuJoCo's warnings of a diverged simulation (NaN, inf or > 1e10 in qpos, qvel, qacc)
_BAD_STATE = (
    (mujoco.mjtWarning.mjWARN_BADQPOS, "position"),
    (mujoco.mjtWarning.mjWARN_BADQVEL, "velocity"),
    (mujoco.mjtWarning.mjWARN_BADQACC, "acceleration"),
)


class DivergenceWatch:
    """MuJoCo's divergence warnings of one model, by actor.

    Parameters:
        model, data: the compiled MuJoCo model and its data.
        bodies: each actor's ``(name, root body name)``.
    """

    def __init__(
        self, model: mujoco.MjModel, data: mujoco.MjData, bodies: Sequence[tuple[str, str]]
    ) -> None:
        self.model = model
        self._bodies = tuple(bodies)
        self._stats = tuple(data.warning[int(w)] for w, _ in _BAD_STATE)
        self.reset()

    def _counts(self) -> tuple[int, ...]:
        return tuple(stat.number for stat in self._stats)

    def reset(self) -> None:
        """Take the warnings so far as seen."""
        self._seen = self._counts()
        self._total = sum(self._seen)

    def warned(self) -> bool:
        """Whether MuJoCo warned of a divergence since the last :meth:`report`/:meth:`reset`."""
        a, b, c = self._stats
        warned: bool = a.number + b.number + c.number != self._total
        return warned

    def report(self) -> tuple[str, str]:
        """``(actor, what)`` of the new warning (``actor`` ``""`` when none is named);
        the warnings so far are then taken as seen."""
        m = self.model
        counts = self._counts()
        found: tuple[str, str] | None = None
        for (warning, what), stat, now, seen in zip(
            _BAD_STATE, self._stats, counts, self._seen, strict=True
        ):
            if now == seen or found is not None:
                continue
            index = int(stat.lastinfo)
            if warning == mujoco.mjtWarning.mjWARN_BADQPOS:
                joints = np.flatnonzero(m.jnt_qposadr <= index)
                body = int(m.jnt_bodyid[joints[-1]]) if len(joints) else -1
            else:
                body = int(m.dof_bodyid[index]) if 0 <= index < m.nv else -1
            found = (
                self._actor_of_body(body),
                f"NaN, infinite or huge {what} in the physics (MuJoCo reset the simulation)",
            )
        self._seen = counts
        self._total = sum(counts)
        return found or ("", "MuJoCo reported an unstable simulation")

    def _actor_of_body(self, body: int) -> str:
        if body < 0:
            return ""
        root = int(self.model.body_rootid[body])
        for name, body_name in self._bodies:
            if mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, body_name) == root:
                return name
        return ""
