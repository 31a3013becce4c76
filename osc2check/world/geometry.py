"""Reference-line geometry: OpenDRIVE's five plan-view primitives, evaluated exactly.

A road's reference line is a chain of :class:`Geometry` records, each starting at
its own pose ``(x, y, hdg)`` at road coordinate ``s``. :func:`evaluate` gives the
position, heading and curvature at any arc lengths ``ds`` from a record's start
(numpy arrays in and out):

* ``line``: straight.
* ``arc``: constant curvature, in closed form.
* ``spiral``: curvature linear in ``ds`` (a clothoid). The heading is the exact
  quadratic ``hdg + k0 ds + c ds^2 / 2``; the position is its integral, taken by
  Gauss-Legendre quadrature (numpy's ``leggauss``, 10 nodes) over pieces of at
  most 1 m. On such a piece the integrand ``cos``/``sin`` of a quadratic is
  resolved to machine precision, and one code path serves every start
  curvature. (Fresnel integrals, e.g. ``scipy.special.fresnel``, give the same
  numbers for a spiral that starts straight, but a spiral between two non-zero
  curvatures must be shifted onto the standard clothoid, which is ill-conditioned
  for gentle spirals and undefined for a constant one; the tests use SciPy's
  Fresnel integrals as the independent oracle instead.)
* ``poly3``: a cubic ``v(u)`` in the record's local frame (deprecated in 1.6 but
  still written by tools).
* ``paramPoly3``: cubics ``u(p)``, ``v(p)`` with ``pRange`` ``arcLength``
  (``p`` in ``[0, length]``) or ``normalized`` (``p`` in ``[0, 1]``).

For both polynomial kinds ``ds`` is the true arc length: the curve's length
``L(p)`` is tabulated by quadrature of ``|dP/dp|`` and inverted (interpolation
then Newton steps), then scaled so the record ends at its declared ``length``,
as esmini does. Heading and curvature come from the analytic derivatives.

:func:`sample_spacing` chooses where to sample a record so that the chord of a
dense polyline stays within ``tolerance`` of the curve (sagitta ``h^2 k / 8``), at
most one sample a centimetre.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np

from osc2check.world.arrays import FloatArray
from osc2check.world.budget import MIN_STEP

__all__ = [
    "Cubic",
    "Geometry",
    "GeometryKind",
    "GeometrySamples",
    "cubic_profile",
    "cubic_slope",
    "evaluate",
    "sample_spacing",
]

GeometryKind = Literal["line", "arc", "spiral", "poly3", "paramPoly3"]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(10)
_PIECE = 1.0  # longest quadrature piece (m)


@dataclass(frozen=True, slots=True)
class Geometry:
    """One plan-view record.

    Parameters:
        kind: ``line``, ``arc``, ``spiral``, ``poly3`` or ``paramPoly3``.
        s: road coordinate of the record's start.
        x, y, hdg: start pose in the world frame (hdg in rad, counter-clockwise from +x).
        length: arc length of the record (> 0).
        curvature: ``arc`` curvature (1/m, positive turns left).
        curv_start, curv_end: ``spiral`` curvature at the start and end.
        coefficients: ``poly3`` ``(a, b, c, d)``; ``paramPoly3``
            ``(aU, bU, cU, dU, aV, bV, cV, dV)``.
        normalized: ``paramPoly3`` with ``pRange="normalized"``.
        line: source line of the record, for messages.
    """

    kind: GeometryKind
    s: float
    x: float
    y: float
    hdg: float
    length: float
    curvature: float = 0.0
    curv_start: float = 0.0
    curv_end: float = 0.0
    coefficients: tuple[float, ...] = ()
    normalized: bool = False
    line: int | None = None


@dataclass(frozen=True, slots=True)
class GeometrySamples:
    """Pose and curvature at arc lengths ``ds`` from a record's start (arrays of one shape)."""

    x: FloatArray
    y: FloatArray
    heading: FloatArray
    curvature: FloatArray


def evaluate(geometry: Geometry, ds: FloatArray) -> GeometrySamples:
    """Exact pose and curvature of ``geometry`` at arc lengths ``ds`` (0 .. length)."""
    ds = np.asarray(ds, dtype=np.float64)
    match geometry.kind:
        case "line":
            return _arc(geometry, ds, 0.0)
        case "arc":
            return _arc(geometry, ds, geometry.curvature)
        case "spiral":
            return _spiral(geometry, ds)
        case "poly3" | "paramPoly3":
            return _polynomial(geometry, ds)


def max_curvature(geometry: Geometry) -> float:
    """An upper estimate of ``|curvature|`` over the record."""
    match geometry.kind:
        case "line":
            return 0.0
        case "arc":
            return abs(geometry.curvature)
        case "spiral":
            return max(abs(geometry.curv_start), abs(geometry.curv_end))
        case "poly3" | "paramPoly3":
            ds = np.linspace(0.0, geometry.length, 65)
            return float(np.max(np.abs(_polynomial(geometry, ds).curvature)))


def sample_spacing(geometry: Geometry, tolerance: float, max_step: float) -> float:
    """Step along ``geometry`` that keeps chords within ``tolerance`` of the curve, but
    never under ``budget.MIN_STEP`` (the sampling density is bounded, whatever the bend)."""
    kappa = max_curvature(geometry)
    if kappa <= 0.0:
        return max_step
    return max(MIN_STEP, min(max_step, math.sqrt(8.0 * tolerance / kappa)))


# ---------------------------------------------------------------- line and arc


def _arc(g: Geometry, ds: FloatArray, kappa: float) -> GeometrySamples:
    heading = g.hdg + kappa * ds
    if abs(kappa) * g.length < 1e-12:
        x = g.x + ds * math.cos(g.hdg)
        y = g.y + ds * math.sin(g.hdg)
    else:
        x = g.x + (np.sin(heading) - math.sin(g.hdg)) / kappa
        y = g.y - (np.cos(heading) - math.cos(g.hdg)) / kappa
    return GeometrySamples(x, y, heading, np.full_like(ds, kappa))


# ---------------------------------------------------------------- spiral


def _spiral(g: Geometry, ds: FloatArray) -> GeometrySamples:
    k0 = g.curv_start
    rate = (g.curv_end - g.curv_start) / g.length

    def theta(u: FloatArray) -> FloatArray:
        return g.hdg + k0 * u + 0.5 * rate * u * u

    dx, dy = _integrate_direction(theta, ds)
    return GeometrySamples(g.x + dx, g.y + dy, theta(ds), k0 + rate * ds)


def _integrate_direction(
    theta: Callable[[FloatArray], FloatArray], ds: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """``(int_0^ds cos theta, int_0^ds sin theta)`` for every ``ds`` (any order)."""
    flat = ds.ravel()
    order = np.argsort(flat, kind="stable")
    targets = flat[order]
    # Break [0, max] at every target and every _PIECE metres.
    top = float(targets[-1]) if targets.size else 0.0
    grid = np.union1d(np.append(targets, 0.0), np.arange(0.0, top, _PIECE))
    a, b = grid[:-1], grid[1:]
    half = 0.5 * (b - a)
    mid = 0.5 * (b + a)
    u = mid[:, None] + half[:, None] * _NODES[None, :]
    angle = theta(u)
    cx = np.concatenate(([0.0], np.cumsum(half * (np.cos(angle) @ _WEIGHTS))))
    cy = np.concatenate(([0.0], np.cumsum(half * (np.sin(angle) @ _WEIGHTS))))
    at = np.searchsorted(grid, targets)
    x = np.empty_like(flat)
    y = np.empty_like(flat)
    x[order] = cx[at]
    y[order] = cy[at]
    return x.reshape(ds.shape), y.reshape(ds.shape)


# ---------------------------------------------------------------- poly3 and paramPoly3


def _local_polynomials(
    g: Geometry,
) -> tuple[np.polynomial.Polynomial, np.polynomial.Polynomial, float]:
    """``u(p)``, ``v(p)`` in the record's local frame and the end parameter ``p1``."""
    Poly = np.polynomial.Polynomial
    if g.kind == "poly3":
        a, b, c, d = g.coefficients
        u = Poly([0.0, 1.0])
        v = Poly([a, b, c, d])
        # poly3 runs over u; find the u whose arc length is `length`.
        return u, v, _end_parameter(u, v, g.length)
    au, bu, cu, du, av, bv, cv, dv = g.coefficients
    p1 = 1.0 if g.normalized else g.length
    return Poly([au, bu, cu, du]), Poly([av, bv, cv, dv]), p1


def _speed(du: np.polynomial.Polynomial, dv: np.polynomial.Polynomial, p: FloatArray) -> FloatArray:
    result: FloatArray = np.hypot(du(p), dv(p))
    return result


def _arc_length_table(
    u: np.polynomial.Polynomial, v: np.polynomial.Polynomial, p1: float, pieces: int
) -> tuple[FloatArray, FloatArray]:
    """Parameters ``p`` (``pieces + 1`` of them) and the arc length from 0 to each."""
    du, dv = u.deriv(), v.deriv()
    p = np.linspace(0.0, p1, pieces + 1)
    half = 0.5 * (p[1:] - p[:-1])
    mid = 0.5 * (p[1:] + p[:-1])
    nodes = mid[:, None] + half[:, None] * _NODES[None, :]
    lengths = half * (_speed(du, dv, nodes) @ _WEIGHTS)
    return p, np.concatenate(([0.0], np.cumsum(lengths)))


def _end_parameter(
    u: np.polynomial.Polynomial, v: np.polynomial.Polynomial, length: float
) -> float:
    """The ``p`` at which the arc length of ``(u, v)`` reaches ``length`` (u(p) = p)."""
    hi = length
    p, table = _arc_length_table(u, v, hi, 64)
    while table[-1] < length:  # v' != 0 makes the curve longer than its u-extent
        hi *= 2.0
        p, table = _arc_length_table(u, v, hi, 64)
    end = float(np.interp(length, table, p))
    pieces = max(16, math.ceil(length / _PIECE))
    du, dv = u.deriv(), v.deriv()
    for _ in range(3):  # Newton on L(end) = length
        reached = float(_arc_length_table(u, v, end, pieces)[1][-1])
        end -= (reached - length) / max(float(np.hypot(du(end), dv(end))), 1e-12)
    return end


def _polynomial(g: Geometry, ds: FloatArray) -> GeometrySamples:
    u, v, p1 = _local_polynomials(g)
    du, dv = u.deriv(), v.deriv()
    ddu, ddv = du.deriv(), dv.deriv()
    pieces = max(16, int(math.ceil(g.length / _PIECE)))
    p_table, s_table = _arc_length_table(u, v, p1, pieces)
    # ds -> arc length along the polynomial (scaled to the record's length) -> p.
    target = np.clip(ds, 0.0, g.length) * (s_table[-1] / g.length)
    p = np.interp(target, s_table, p_table)
    # Newton on L(p) = target, starting in the right piece of the table.
    lo_index = np.clip(np.searchsorted(p_table, p) - 1, 0, pieces - 1)
    for _ in range(3):
        base = p_table[lo_index]
        half = 0.5 * (p - base)
        nodes = (base + half)[..., None] + half[..., None] * _NODES
        partial = half * (_speed(du, dv, nodes) @ _WEIGHTS)
        error = s_table[lo_index] + partial - target
        p = p - error / np.maximum(_speed(du, dv, p), 1e-12)
    up, vp = du(p), dv(p)
    cos_h, sin_h = math.cos(g.hdg), math.sin(g.hdg)
    lu, lv = u(p), v(p)
    x = g.x + lu * cos_h - lv * sin_h
    y = g.y + lu * sin_h + lv * cos_h
    heading = g.hdg + np.arctan2(vp, up)
    curvature = (up * ddv(p) - vp * ddu(p)) / np.maximum(np.hypot(up, vp), 1e-12) ** 3
    return GeometrySamples(x, y, heading, curvature)


# ---------------------------------------------------------------- cubic profiles


@dataclass(frozen=True, slots=True)
class Cubic:
    """``a + b ds + c ds^2 + d ds^3`` with ``ds = s - self.s``, valid until the next record.

    OpenDRIVE writes lane offsets, lane widths and borders, and elevations this way.
    """

    s: float
    a: float
    b: float = 0.0
    c: float = 0.0
    d: float = 0.0


def cubic_profile(records: tuple[Cubic, ...], s: FloatArray, before: float = 0.0) -> FloatArray:
    """Value of a piecewise cubic profile at ``s``; ``before`` ahead of the first record."""
    s = np.asarray(s, dtype=np.float64)
    if not records:
        return np.full_like(s, before)
    starts = np.array([r.s for r in records])
    coeffs = np.array([(r.a, r.b, r.c, r.d) for r in records])
    which = np.searchsorted(starts, s, side="right") - 1
    inside = which >= 0
    k = np.clip(which, 0, None)
    ds = s - starts[k]
    a, b, c, d = (coeffs[k][..., i] for i in range(4))
    value: FloatArray = a + ds * (b + ds * (c + ds * d))
    return np.where(inside, value, before)


def cubic_slope(records: tuple[Cubic, ...], s: FloatArray) -> FloatArray:
    """Derivative in ``s`` of :func:`cubic_profile` (0 ahead of the first record)."""
    s = np.asarray(s, dtype=np.float64)
    if not records:
        return np.zeros_like(s)
    starts = np.array([r.s for r in records])
    coeffs = np.array([(r.b, r.c, r.d) for r in records])
    which = np.searchsorted(starts, s, side="right") - 1
    k = np.clip(which, 0, None)
    ds = s - starts[k]
    b, c, d = (coeffs[k][..., i] for i in range(3))
    slope: FloatArray = b + ds * (2.0 * c + 3.0 * d * ds)
    return np.where(which >= 0, slope, 0.0)
