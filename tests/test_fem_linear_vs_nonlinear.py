"""Linear pad levels against the neo-Hookean reference (workbench.fem.linear_vs_nonlinear)."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.fem.linear_vs_nonlinear import (
    FIDELITY_CASES,
    fidelity_case,
    fidelity_setup,
    transferred_correction,
)


def test_setup_is_the_16_x_20_x_5_mm_layer_and_two_indenters_touching_its_centre():
    geom, mat, cases = fidelity_setup([4, 6, 2], 0.45)
    assert (geom.width, geom.length, geom.thickness) == (0.016, 0.02, 0.005)
    assert (geom.nx, geom.ny, geom.nz) == (4, 6, 2) and mat.nu == 0.45
    assert tuple(cases) == FIDELITY_CASES
    centre = np.array([[0.0, 0.0, geom.thickness]])
    for obstacle in cases.values():
        d, _ = obstacle.signed_distance(centre)
        assert abs(d[0]) < 1e-15  # first touch at the face's centre: no preload


def test_unknown_case_is_refused():
    with pytest.raises(ValueError, match="name must be one of"):
        fidelity_case("sphere R20", [4, 6, 2], 0.45, [0.02])


@pytest.mark.jit_only("neo-Hookean load steps: 15 s as pure Python; its kernel runs in test_fem_nonlinear.py")
def test_small_strain_agreement_and_large_strain_gap():
    """At δ/h = 2 % (small strain) the condensed pad with full integration, the reference's
    discretization, is within 3 % of the neo-Hookean force and pressure field; the full-mesh
    linear level is the condensed SRI level to round-off (condensation is exact); SRI is the
    softer linear level (full integration locks at nu = 0.45 on 2.5 mm hexes); and the
    neo-Hookean force grows with δ."""
    rows = fidelity_case("cylinder R15", [4, 6, 2], 0.45, [0.02, 0.2], full_mesh=True)
    assert len(rows) == 2 * 4
    assert list(rows[0]) == [
        "case",
        "delta_over_h",
        "nl_force_N",
        "nl_peak_kPa",
        "nl_area_mm2",
        "level",
        "seconds",
        "force_rel_err",
        "peak_rel_err",
        "area_rel_err",
        "pressure_rel_l2",
    ]
    small = {r["level"]: r for r in rows if r["delta_over_h"] == pytest.approx(0.02)}
    ref = small["nonlinear (neo-Hookean)"]
    assert ref["force_rel_err"] == ref["pressure_rel_l2"] == 0.0
    assert abs(small["condensed full"]["force_rel_err"]) < 0.03
    assert small["condensed full"]["pressure_rel_l2"] < 0.03
    sri, full_mesh = small["condensed SRI"], small["linear full mesh"]
    for key in ("force_rel_err", "peak_rel_err", "pressure_rel_l2"):
        assert full_mesh[key] == pytest.approx(sri[key], rel=1e-9, abs=1e-12)
    assert sri["force_rel_err"] < small["condensed full"]["force_rel_err"]
    nl = [r["nl_force_N"] for r in rows if r["level"].startswith("nonlinear")]
    assert nl[1] > nl[0] > 0


def _sri_row(
    case: str, delta_over_h: float, force_err: float, peak_err: float, level="condensed SRI"
) -> dict:
    return {
        "case": case,
        "delta_over_h": delta_over_h,
        "level": level,
        "force_rel_err": force_err,
        "peak_rel_err": peak_err,
    }


def test_transferred_correction_by_hand():
    """Calibrated on A at δ/h = 20 %: F_nl,A / F_lin,A = 1 / (1 + e_A); applied to B's linear
    force F_nl,B (1 + e_B), the corrected error is (1 + e_B) / (1 + e_A) − 1 — with
    e_A = −0.2, e_B = −0.3: 0.7 / 0.8 − 1 = −0.125.  Small-strain levels (2 %), levels other
    than condensed SRI and δ/h missing for one indenter are left out."""
    rows = [
        _sri_row("A", 0.2, -0.2, -0.1),
        _sri_row("B", 0.2, -0.3, -0.1),
        _sri_row("A", 0.02, -0.5, -0.5),
        _sri_row("B", 0.02, -0.5, -0.5),
        _sri_row("A", 0.4, -0.4, -0.4),
        _sri_row("B", 0.2, 0.9, 0.9, level="condensed full"),
    ]
    got = transferred_correction(rows)
    assert sorted(got) == ["force: A -> B 20%", "force: B -> A 20%", "peak: A -> B 20%", "peak: B -> A 20%"]
    assert got["force: A -> B 20%"]["uncorrected"] == -0.3
    assert got["force: A -> B 20%"]["corrected"] == pytest.approx(0.7 / 0.8 - 1, rel=1e-14)
    assert got["force: B -> A 20%"]["corrected"] == pytest.approx(0.8 / 0.7 - 1, rel=1e-14)
    assert got["peak: A -> B 20%"]["corrected"] == pytest.approx(0.0, abs=1e-15)
