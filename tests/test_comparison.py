"""A peer's errors against a reference (workbench.peers.comparison): zero for the reference
itself, the known values for a contact with twice the pressure, MuJoCo's point contact measured
by its coefficients, and margins that scale with the jaw force as the disturbances do."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.fem.contact import solve_contact
from workbench.fem.extract import extract_profile, face_grid, nodal_pressures
from workbench.fem.material import Material
from workbench.fem.obstacles import Sphere
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.peers import metrics
from workbench.peers.comparison import compare, fem_row, grasp_margins, reference_measures
from workbench.peers.hertz import hertz_profile
from workbench.peers.mujoco_cone import patch_coefficients

MU = 0.5
R, DELTA = 15e-3, 0.5e-3


@pytest.fixture(scope="module")
def hertz():
    prof = hertz_profile(R, DELTA, 1e6, 0.45)
    grid, _ = metrics.face_grid_points(16e-3, 20e-3, 0.4e-3)
    ref = {
        "force_N": metrics.jaw_force(prof),
        "area": np.pi * R * DELTA,
        "field": metrics.field_from_elements(prof, grid),
        "torsion_length": metrics.torsion_length(prof, MU),
        "supports": metrics.supports(prof, MU),
    }
    return prof, grid, ref


def test_the_reference_against_itself_has_no_error_and_twice_the_pressure_the_known_ones(hertz):
    prof, grid, ref = hertz
    row = {"profile": prof, "area": ref["area"], "field": ("elements",)}
    c = compare(row, ref, grid, MU)
    for k in ("force_rel_err", "area_rel_err", "pressure_rel_l2", "torsion_rel_err", "torque_rel_err"):
        assert c[k] == pytest.approx(0.0, abs=1e-12), k
    assert c["support_max_rel_err"] == pytest.approx(0.0, abs=1e-12)
    assert c["torsion_length_mm"] == pytest.approx(1e3 * ref["torsion_length"], rel=1e-15)
    # twice the pressure on the same patch: twice the force and torque, the same torsion length
    c2 = compare({**row, "profile": prof.with_pressures(2 * prof.pressures)}, ref, grid, MU)
    assert c2["force_rel_err"] == pytest.approx(1.0, rel=1e-12)
    assert c2["pressure_rel_l2"] == pytest.approx(1.0, rel=1e-12)
    assert c2["torsion_rel_err"] == pytest.approx(0.0, abs=1e-12)
    assert c2["torque_rel_err"] == pytest.approx(1.0, rel=1e-12)
    assert c2["area_rel_err"] == 0.0


def test_mujoco_is_measured_by_its_coefficients(hertz):
    prof, grid, ref = hertz
    coef = patch_coefficients(MU, R, DELTA, "hertz")
    c = compare({"profile": None, "coefficients": coef}, ref, grid, MU)
    for k in ("force_N", "force_rel_err", "area_mm2", "area_rel_err", "pressure_rel_l2", "torque_rel_err"):
        assert c[k] is None
    a = np.sqrt(R * DELTA)
    assert c["torsion_length_mm"] == pytest.approx(3 * np.pi * a / 16 * 1e3, rel=1e-12)
    # Hertz's torsion per unit jaw force is 3πa/16 up to the cap's tilt, O(a²/R²)
    assert abs(c["torsion_rel_err"]) < a * a / (R * R)
    assert len(c["support_rel_err"]) == 6


def test_a_fem_row_against_the_measures_of_the_same_solve_has_no_error():
    geom = PadGeometry(16e-3, 20e-3, 5e-3, 8, 10, 3)
    pad = condense_pad(geom, Material(1e6, 0.45))
    obs = Sphere((0.0, 0.0, 5e-3 + R), R)
    sol = solve_contact(pad, obs, DELTA)
    prof = extract_profile(pad, sol, obs)
    _, area0 = face_grid(pad.face_xy)
    row = fem_row(pad, area0, sol, prof)
    assert row["area"] == pytest.approx(area0[sol.lam > 0].sum(), rel=1e-15)
    grid, _ = metrics.face_grid_points(16e-3, 20e-3, 0.4e-3)
    ref_row = {"profile": prof, "area": row["area"], "p_node": nodal_pressures(pad, sol.lam)}
    ref = reference_measures(ref_row, pad.face_xy, grid, MU)
    # the jaw reads the net normal force: the solve's, less the patch's tilt (within δ/R)
    assert sol.force * (1 - DELTA / R) < ref["force_N"] <= sol.force
    c = compare(row, ref, grid, MU)
    for k in ("force_rel_err", "area_rel_err", "pressure_rel_l2", "torsion_rel_err"):
        assert c[k] == pytest.approx(0.0, abs=1e-12), k


def test_margins_scale_with_the_jaw_force_as_the_disturbances_do():
    coef = patch_coefficients(MU, R, DELTA, "diameter")
    point, center = np.array([0.0, 0.0, 5e-3]), np.array([0.0, 0.0, 5e-3 + R])
    cone = {"kind": "cone", "coefficients": coef, "force": 1.0, "point": point}
    kw = {"seed": 0, "n_disturbances": 3, "steps": 6}
    m1 = grasp_margins({"a": cone, "b": dict(cone)}, center, MU, scale=1.0, **kw)
    m2 = grasp_margins({"a": {**cone, "force": 2.0}}, center, MU, scale=2.0, **kw)
    assert m1["a"].shape == (3,) and (m1["a"] > 0).all()
    assert m1["a"].tolist() == m1["b"].tolist()  # the same disturbances for every peer
    assert m2["a"] == pytest.approx(m1["a"], rel=1e-9)  # friction is linear in the normal force
