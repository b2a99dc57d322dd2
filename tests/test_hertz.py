"""Hertz sphere on an elastic half-space (workbench.peers.hertz): closed forms against quadrature,
the profile's force and torsional capacity against the closed forms, scaling, careless input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from workbench.peers.hertz import (
    effective_modulus,
    hertz_contact_radius,
    hertz_force,
    hertz_p0,
    hertz_pressure,
    hertz_profile,
    hertz_torsion_capacity,
)
from workbench.wrench import normal_wrench, w_max

R, DELTA, E, NU, MU = 0.02, 1e-3, 1.0e6, 0.45, 0.5


def test_closed_forms_agree_with_the_pressure_integrals():
    # F = ∫ p dA = 2π p0 ∫_0^a √(1 - r²/a²) r dr = 2π p0 a² / 3, so p0 = 3F / (2π a²); and
    # τ_max / μ = ∫ p r dA = 2π p0 a³ ∫_0^1 s² √(1 - s²) ds = 2π p0 a³ π/16 = 3π F a / 16
    a = hertz_contact_radius(R, DELTA)
    F = hertz_force(R, DELTA, E, NU)
    assert a == pytest.approx(np.sqrt(R * DELTA), rel=1e-15)
    assert F == pytest.approx(4 / 3 * E / (1 - NU**2) * np.sqrt(R) * DELTA**1.5, rel=1e-15)
    assert effective_modulus(E, NU) == pytest.approx(E / (1 - NU**2), rel=1e-15)
    p = lambda r: float(hertz_pressure(np.array([r]), R, DELTA, E, NU)[0])  # noqa: E731
    force, _ = quad(lambda r: p(r) * 2 * np.pi * r, 0, a, epsabs=0, epsrel=1e-12)
    torque, _ = quad(lambda r: MU * p(r) * 2 * np.pi * r * r, 0, a, epsabs=0, epsrel=1e-12)
    assert force == pytest.approx(F, rel=1e-9)
    assert torque == pytest.approx(hertz_torsion_capacity(R, DELTA, E, NU, MU), rel=1e-9)
    assert hertz_p0(R, DELTA, E, NU) == pytest.approx(
        2 * effective_modulus(E, NU) / np.pi * np.sqrt(DELTA / R)
    )
    assert hertz_pressure(np.array([a, 2 * a]), R, DELTA, E, NU).tolist() == [0.0, 0.0]


def test_profile_carries_the_hertz_force_and_torsional_capacity_exactly():
    prof = hertz_profile(R, DELTA, E, NU, n_rings=12, n_sectors=24)
    F = hertz_force(R, DELTA, E, NU)
    a = hertz_contact_radius(R, DELTA)
    assert len(prof) == 12 * 24
    # each element carries the closed-form ring integral: Σ p a = F to round-off
    assert prof.F == pytest.approx(F, rel=1e-12)
    # elements sit at their ring's force-weighted mean radius and a rotation about the axis slips
    # tangentially to the cap, so the 6DFW's torsional capacity is the closed form to round-off
    assert w_max(prof, MU)[5] == pytest.approx(3 * np.pi * MU * F * a / 16, rel=1e-12)
    # on the sphere cap, normals outward from the sphere (into the pad, below)
    center = np.array([0.0, 0.0, R])
    assert np.allclose(np.linalg.norm(prof.centers - center, axis=1), R, rtol=1e-14)
    assert np.allclose(prof.normals, (prof.centers - center) / R, atol=1e-14)
    assert (prof.normals[:, 2] < 0).all()
    assert np.allclose(prof.pressure_center[:2], 0.0, atol=1e-15)
    # net normal force on the object (+z) is F up to the cap's tilt, 1 - O(a²/R²)
    fz = normal_wrench(prof)[2]
    assert 0 < 1 - fz / F < (a / R) ** 2


def test_profile_pressure_follows_the_hertz_distribution():
    # the element pressure is its ring force over the cap area; times cap/footprint area it is the
    # ring's mean Hertz pressure, which approaches p(r̄) as rings narrow (away from the rim's √ edge)
    n = 40
    prof = hertz_profile(R, DELTA, E, NU, n_rings=n, n_sectors=8)
    a = hertz_contact_radius(R, DELTA)
    r = np.linalg.norm(prof.centers[:, :2], axis=1)[::8]
    edges = np.linspace(0, a, n + 1)
    footprint = np.pi * np.diff(edges**2) / 8
    mean_p = prof.pressures[::8] * prof.areas[::8] / footprint
    exact = hertz_pressure(r, R, DELTA, E, NU)
    p0 = hertz_p0(R, DELTA, E, NU)
    assert np.abs(mean_p - exact)[: n - 2].max() < 2e-3 * p0
    assert mean_p[0] == pytest.approx(p0, rel=1e-3)


def test_scale_covariance():
    # lengths × s at fixed E: p0 ∝ √(δ/R) fixed, so F × s², τ × s³ (CONVENTIONS.md, to 1e-9)
    s = 3.7
    p1 = hertz_profile(R, DELTA, E, NU, 6, 12)
    p2 = hertz_profile(s * R, s * DELTA, E, NU, 6, 12)
    assert p2.F == pytest.approx(s**2 * p1.F, rel=1e-9)
    assert w_max(p2, MU)[5] == pytest.approx(s**3 * w_max(p1, MU)[5], rel=1e-9)
    assert hertz_force(s * R, s * DELTA, E, NU) == pytest.approx(
        s**2 * hertz_force(R, DELTA, E, NU), rel=1e-12
    )


def test_profile_elsewhere_is_the_same_profile_moved():
    c = np.array([0.01, -0.02, 0.03])
    p1 = hertz_profile(R, DELTA, E, NU, 4, 8)
    p2 = hertz_profile(R, DELTA, E, NU, 4, 8, center=c)
    assert np.allclose(p2.centers - p1.centers, c - [0, 0, R], atol=1e-15)
    assert np.allclose(w_max(p1, MU), w_max(p2, MU), rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"R": 20.0}, "millimetres"),  # a radius in mm
        ({"delta": -1e-3}, "positive depth"),
        ({"delta": float("nan")}, "finite"),
        ({"delta": 1.0}, "1 mm = 1e-3"),  # δ in mm: above R
        ({"E": 1.0}, "1 MPa = 1e6"),  # E in MPa
        ({"nu": 0.5}, "Poisson"),
        ({"n_rings": 0}, "n_rings"),
        ({"n_sectors": 2}, "n_sectors"),
        ({"n_rings": 2.5}, "int"),
        ({"center": [0, 0]}, r"\(3,\)"),
    ],
)
def test_careless_input_raises_saying_what_and_the_fix(kwargs, match):
    args = {"R": R, "delta": DELTA, "E": E, "nu": NU, "n_rings": 4, "n_sectors": 8} | kwargs
    with pytest.raises(ValueError, match=match):
        hertz_profile(**args)


def test_closed_forms_validate_too():
    with pytest.raises(ValueError, match="millimetres"):
        hertz_force(20.0, 1.0, E, NU)
    with pytest.raises(ValueError, match="friction"):
        hertz_torsion_capacity(R, DELTA, E, NU, -0.5)
    with pytest.raises(ValueError, match=">= 0"):
        hertz_pressure(np.array([-1e-3]), R, DELTA, E, NU)
