"""Free bodies (vehicles' and trailers' chassis on a free joint): planar read-out, drag, placing.

:func:`free_body_state` reads the planar state of many bodies at once from their
``qpos``/``qvel`` rows; :func:`drag_forces` is the aerodynamic drag on them;
:func:`set_free_body` moves one to a new pose and speed, keeping its pitch and roll.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

__all__ = ["FreeBodyState", "drag_forces", "free_body_state", "set_free_body"]


#: planar state of n free-joint bodies, arrays of n rows: position (n, 2), yaw, world
#: velocity (n, 3), yaw rate, cos and sin of yaw, speed along the heading and left of it
FreeBodyState = tuple[
    np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray
]


def free_body_state(q: np.ndarray, v: np.ndarray) -> FreeBodyState:
    """The planar state from free-joint ``qpos`` rows ``q`` (n, 7) and ``qvel`` rows ``v``
    (n, 6): yaw from the quaternion, speeds along and across the heading (see
    :data:`FreeBodyState` for the order)."""
    w, qx, qy, qz = q[:, 3], q[:, 4], q[:, 5], q[:, 6]
    yaw = np.arctan2(2.0 * (w * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    c, s = np.cos(yaw), np.sin(yaw)
    # a plain tuple: read per tick, and a named one costs more to make
    return (
        q[:, :2],
        yaw,
        v[:, :3],
        v[:, 5],
        c,
        s,
        v[:, 0] * c + v[:, 1] * s,
        -v[:, 0] * s + v[:, 1] * c,
    )


def drag_forces(coefficient: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """Aerodynamic drag (n, 2) on bodies moving at world velocities ``vel`` (n, >= 2):
    ``coefficient`` (0.5 rho Cd A per body) times the speed squared, against the motion."""
    result: np.ndarray = -(coefficient * np.hypot(vel[:, 0], vel[:, 1]))[:, None] * vel[:, :2]
    return result


def set_free_body(
    m: mujoco.MjModel,
    d: mujoco.MjData,
    q: int,
    v: int,
    spin_dof: np.ndarray,
    wheel_body: np.ndarray,
    x: float,
    y: float,
    yaw: float,
    speed: float,
) -> None:
    """Move a vehicle's or trailer's free body (``qpos`` at ``q``, ``qvel`` at ``v``) to
    ``(x, y)`` heading ``yaw``, keeping its height, pitch and roll, at ``speed`` along the
    heading; its wheels (``spin_dof``, ``wheel_body``) get the matching spin."""
    old = d.qpos[q + 3 : q + 7].copy()
    tilt = _quat_mul(_yaw_quat(-_quat_yaw(old)), old)
    d.qpos[q : q + 2] = (x, y)
    d.qpos[q + 3 : q + 7] = _quat_mul(_yaw_quat(yaw), tilt)
    d.qvel[v : v + 6] = (speed * math.cos(yaw), speed * math.sin(yaw), 0.0, 0.0, 0.0, 0.0)
    mujoco.mj_kinematics(m, d)
    d.qvel[spin_dof] = speed / d.xpos[wheel_body, 2]  # rolling radius = wheel centre height


def _yaw_quat(yaw: float) -> np.ndarray:
    return np.array([math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw)])


def _quat_yaw(q: np.ndarray) -> float:
    w, x, y, z = (float(v) for v in q)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.empty(4)
    mujoco.mju_mulQuat(out, np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    return out
