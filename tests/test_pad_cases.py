"""The peers' contacts (workbench.peers.pad_cases): each obstacle touches the pad face at δ = 0
above its centre with the curvature radius of its surface there, and the neo-Hookean reference
matches the linear pad at small strain."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.fem.contact import solve_contact
from workbench.fem.pad import condense_pad
from workbench.peers.pad_cases import CASES, drake_pad, reference_case, setup_case

CONFIG = {
    "seed": 0,
    "E": 1.0e6,
    "nu": 0.45,
    "pad_mm": [16.0, 20.0, 5.0],
    "pad_cells": [8, 10, 3],
    "radius_mm": 15.0,
    "ellipse_mm": [30.0, 20.0],
    "bottle": {"index": 0, "height": 0.5, "mesh": [64, 80]},
    "ellipse_sections": 720,
    "deltas_mm": [0.05],
    "reference_stabilization": 0.1,
}


@pytest.mark.parametrize("case", ["sphere", "cylinder", "elliptic_cylinder"])
def test_each_analytic_case_touches_the_pad_face_above_its_centre(case):
    geom, mat, obs, c, rho = setup_case(case, CONFIG)
    h = 5e-3
    assert (geom.width, geom.length, geom.thickness) == pytest.approx((16e-3, 20e-3, h), rel=1e-15)
    assert (mat.E, mat.nu) == (1.0e6, 0.45)
    d, _ = obs.signed_distance(np.array([[0.0, 0.0, h]]))
    assert d[0] == pytest.approx(0.0, abs=1e-12)  # touching at δ = 0
    a, b = 30e-3, 20e-3
    centre_height, radius = {"elliptic_cylinder": (a, b * b / a)}.get(case, (15e-3, 15e-3))
    assert c == pytest.approx([0.0, 0.0, h + centre_height], abs=1e-15)
    assert rho == pytest.approx(radius, rel=1e-12)  # b²/a: the ellipse's radius at its major vertex
    assert case in CASES


def test_cells_override_the_pad_mesh():
    geom, *_ = setup_case("sphere", CONFIG, [4, 5, 2])
    assert (geom.nx, geom.ny, geom.nz) == (4, 5, 2)


@pytest.mark.jit_only("the neo-Hookean load stepping on 16 x 20 x 5 hexes runs its kernels as Python")
def test_the_neo_hookean_reference_matches_the_linear_pad_at_small_strain():
    # the experiment's 1 mm hexes at δ/h = 2 %: full 2x2x2 integration locks (+10 % force against
    # the SRI linear pad); the reference's stabilized integration must not
    config = {**CONFIG, "pad_cells": [16, 20, 5], "deltas_mm": [0.1]}
    ref = reference_case("sphere", config)
    ((d, row),) = ref["rows"].items()
    assert d == pytest.approx(0.1e-3, rel=1e-15) and ref["case"] == "sphere" and ref["seconds"] > 0
    geom, mat, obs, _, _ = setup_case("sphere", config)
    lin = solve_contact(condense_pad(geom, mat), obs, d)
    assert row["force"] == pytest.approx(lin.force, rel=0.05)
    assert row["p_node"].shape == (len(ref["face_xy"]),) and (row["p_node"] >= 0).all()
    assert 0 < row["area"] < np.pi * 15e-3 * 2 * d  # within the undeformed overlap disc, 2Rδ


def test_drake_pad_gives_a_pad_or_says_why_not():
    geom, _, obs, _, _ = setup_case("sphere", CONFIG)
    pad, why = drake_pad("sphere", obs, geom, CONFIG, 0.05)
    if pad is None:
        assert "Drake" in why or "drake" in why
    else:
        assert why == ""
        prof = pad.profile(0.5e-3)
        # Winkler law of the hydroelastic box: F ~ (E/h) × the overlap volume π δ² (3R - δ) / 3
        R, d = 15e-3, 0.5e-3
        kV = 1e6 / 5e-3 * np.pi * d * d * (3 * R - d) / 3
        assert prof.F == pytest.approx(kV, rel=0.1)
