"""Each plan-view primitive against its closed form (and SciPy's Fresnel integrals)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from osc2check.world.geometry import Cubic, Geometry, cubic_profile, cubic_slope, evaluate

DS = np.linspace(0.0, 80.0, 161)


def test_line_points_heading_and_curvature() -> None:
    g = Geometry("line", 5.0, 1.0, 2.0, 0.7, 80.0)
    r = evaluate(g, DS)
    assert np.allclose(r.x, 1.0 + DS * math.cos(0.7), atol=1e-12)
    assert np.allclose(r.y, 2.0 + DS * math.sin(0.7), atol=1e-12)
    assert np.allclose(r.heading, 0.7) and np.all(r.curvature == 0.0)


@pytest.mark.parametrize("curvature", [0.01, -0.04])
def test_arc_has_constant_curvature_and_stays_on_its_circle(curvature: float) -> None:
    g = Geometry("arc", 0.0, 3.0, -1.0, 0.3, 80.0, curvature=curvature)
    r = evaluate(g, DS)
    radius = 1.0 / curvature
    cx, cy = 3.0 - radius * math.sin(0.3), -1.0 + radius * math.cos(0.3)
    assert np.allclose(np.hypot(r.x - cx, r.y - cy), abs(radius), atol=1e-9)
    assert np.allclose(r.curvature, curvature)
    assert np.allclose(r.heading, 0.3 + curvature * DS)
    # The heading is the direction of motion: compare with the finite difference.
    step = np.arctan2(np.diff(r.y), np.diff(r.x))
    mid = 0.5 * (r.heading[1:] + r.heading[:-1])
    assert np.allclose(np.angle(np.exp(1j * (step - mid))), 0.0, atol=1e-9)


def test_spiral_from_straight_matches_fresnel_integrals() -> None:
    special = pytest.importorskip("scipy.special")
    g = Geometry("spiral", 0.0, 0.0, 0.0, 0.0, 80.0, curv_start=0.0, curv_end=0.05)
    r = evaluate(g, DS)
    rate = 0.05 / 80.0
    scale = math.sqrt(math.pi / rate)
    fresnel_s, fresnel_c = special.fresnel(DS / scale)
    assert np.allclose(r.x, scale * fresnel_c, atol=1e-9)
    assert np.allclose(r.y, scale * fresnel_s, atol=1e-9)


def test_spiral_between_two_curvatures_matches_shifted_fresnel_integrals() -> None:
    special = pytest.importorskip("scipy.special")
    k0, k1, length = 0.02, -0.01, 60.0
    g = Geometry("spiral", 0.0, 10.0, 20.0, 1.0, length, curv_start=k0, curv_end=k1)
    ds = np.linspace(0.0, length, 31)
    r = evaluate(g, ds)
    # Closed form: heading = h0 + k0 u + c u^2 / 2 = phi0 + c (u + k0/c)^2 / 2 with c < 0.
    c = (k1 - k0) / length
    shift = k0 / c
    phi0 = 1.0 - 0.5 * k0 * k0 / c
    scale = math.sqrt(math.pi / abs(c))
    fs0, fc0 = special.fresnel(shift / scale)
    fs, fc = special.fresnel((ds + shift) / scale)
    # int cos(phi0 - |c| v^2 / 2) dv = cos(phi0) C + sin(phi0) S (in units of scale)
    dx = scale * (math.cos(phi0) * (fc - fc0) + math.sin(phi0) * (fs - fs0))
    dy = scale * (math.sin(phi0) * (fc - fc0) - math.cos(phi0) * (fs - fs0))
    assert np.allclose(r.x, 10.0 + dx, atol=1e-8)
    assert np.allclose(r.y, 20.0 + dy, atol=1e-8)


def test_spiral_curvature_is_linear_in_s_and_heading_quadratic() -> None:
    g = Geometry("spiral", 0.0, 0.0, 0.0, 0.2, 80.0, curv_start=-0.01, curv_end=0.03)
    r = evaluate(g, DS)
    assert np.allclose(np.diff(r.curvature, 2), 0.0, atol=1e-15)
    assert r.curvature[0] == pytest.approx(-0.01) and r.curvature[-1] == pytest.approx(0.03)
    # Curvature from the points themselves (turning of the chords per metre).
    chords = np.unwrap(np.arctan2(np.diff(r.y), np.diff(r.x)))
    measured = np.diff(chords) / 0.5
    assert np.allclose(measured, r.curvature[1:-1], atol=1e-6)


def test_poly3_follows_its_polynomial_in_the_local_frame() -> None:
    a, b, c, d = 0.5, 0.1, 0.002, -1e-5
    g = Geometry("poly3", 0.0, 100.0, 50.0, math.pi / 2, 40.0, coefficients=(a, b, c, d))
    r = evaluate(g, np.linspace(0.0, 40.0, 41))
    # Local frame: u along hdg (+y here), v to its left (-x).
    u = r.y - 50.0
    v = -(r.x - 100.0)
    assert np.allclose(v, a + b * u + c * u**2 + d * u**3, atol=1e-9)
    # The arc length from the start is the evaluation parameter.
    du = np.linspace(0.0, u[-1], 20001)
    length = np.trapezoid(np.sqrt(1 + (b + 2 * c * du + 3 * d * du**2) ** 2), du)
    assert length == pytest.approx(40.0, abs=1e-6)
    slope = b + 2 * c * u + 3 * d * u**2
    assert np.allclose(r.heading, math.pi / 2 + np.arctan(slope), atol=1e-9)
    curvature = (2 * c + 6 * d * u) / (1 + slope**2) ** 1.5
    assert np.allclose(r.curvature, curvature, atol=1e-9)


@pytest.mark.parametrize("normalized", [False, True])
def test_param_poly3_follows_its_polynomials(normalized: bool) -> None:
    length = 30.0
    p1 = 1.0 if normalized else length
    # A gentle S-bend: u grows about linearly, v is a cubic.
    coefficients = (0.0, 29.0 / p1, 0.5 / p1**2, 0.0, 0.0, 0.0, 3.0 / p1**2, -2.0 / p1**3)
    g = Geometry(
        "paramPoly3", 0.0, 0.0, 0.0, 0.0, length, coefficients=coefficients, normalized=normalized
    )
    ds = np.linspace(0.0, length, 61)
    r = evaluate(g, ds)
    au, bu, cu, du_, av, bv, cv, dv = coefficients
    p = np.linspace(0.0, p1, 200001)
    u = au + bu * p + cu * p**2 + du_ * p**3
    v = av + bv * p + cv * p**2 + dv * p**3
    arc = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(u), np.diff(v)))))
    target = ds * arc[-1] / length  # s is scaled so the record ends at its length
    assert np.allclose(r.x, np.interp(target, arc, u), atol=1e-5)
    assert np.allclose(r.y, np.interp(target, arc, v), atol=1e-5)
    assert r.x[-1] == pytest.approx(u[-1], abs=1e-9) and r.y[-1] == pytest.approx(v[-1], abs=1e-9)


def test_cubic_profile_is_piecewise_in_ds_from_each_record() -> None:
    records = (Cubic(0.0, 3.0, 0.1, 0.0, 0.0), Cubic(10.0, 4.0, 0.0, 0.01, -0.001))
    s = np.array([-1.0, 0.0, 5.0, 10.0, 12.0])
    value = cubic_profile(records, s, before=-7.0)
    expected = [-7.0, 3.0, 3.5, 4.0, 4.0 + 0.01 * 4 - 0.001 * 8]
    assert np.allclose(value, expected)
    slope = cubic_slope(records, s)
    assert np.allclose(slope, [0.0, 0.1, 0.1, 0.0, 0.02 * 2 - 0.003 * 4])
