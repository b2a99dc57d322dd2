"""A peer's errors against a reference (workbench.peers.comparison): zero for the reference
itself, the known values for a contact with twice the pressure, MuJoCo's point contact measured
by its coefficients, margins that scale with the jaw force as the disturbances do, the rows'
contact areas (loaded elements; Hertz's π R δ) and the equal-jaw-force margins."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.fem.contact import solve_contact
from workbench.fem.extract import extract_profile, face_grid, nodal_pressures
from workbench.fem.material import Material
from workbench.fem.obstacles import Sphere
from workbench.fem.pad import PadGeometry, condense_pad
from workbench.grasp.margin import MARGIN_SPAN
from workbench.peers import metrics
from workbench.peers.comparison import (
    DISTURBANCE_FORCE_N,
    compare,
    contact_area,
    equal_force_jaws,
    equal_force_margins,
    fem_row,
    grasp_margins,
    hertz_row,
    profile_row,
    reference_measures,
)
from workbench.peers.hertz import hertz_contact_radius, hertz_profile
from workbench.peers.mujoco_cone import patch_coefficients
from workbench.profile import ContactProfile

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


def test_a_profiles_contact_area_counts_its_loaded_elements_only():
    # four elements of 1, 2, 3, 4 mm², the second unloaded (as Drake's clipped rim can be)
    c = np.c_[np.arange(4) * 1e-3, np.zeros(4), np.zeros(4)]
    prof = ContactProfile(
        c,
        np.tile([0.0, 0.0, 1.0], (4, 1)),
        np.array([1.0, 2.0, 3.0, 4.0]) * 1e-6,
        np.array([5.0, 0.0, 1.0, 2.0]) * 1e3,
    )
    assert contact_area(prof) == pytest.approx(8e-6, rel=1e-15)
    row = profile_row(prof)
    assert row["profile"] is prof and row["area"] == contact_area(prof) and row["field"] == ("elements",)
    loaded = prof.with_pressures(np.full(4, 1e3))
    assert contact_area(loaded) == pytest.approx(10e-6, rel=1e-15)


def test_the_hertz_row_has_the_hertz_contact_area(hertz):
    prof, _, _ = hertz
    row = hertz_row(prof, R, DELTA)
    a = hertz_contact_radius(R, DELTA)
    assert row["area"] == pytest.approx(np.pi * a * a, rel=1e-15)
    assert row["area"] == pytest.approx(np.pi * 15e-3 * 0.5e-3, rel=1e-15)  # 23.56 mm²
    assert row["profile"] is prof and row["field"] == ("elements",)
    with pytest.raises(ValueError, match="delta"):
        hertz_row(prof, R, -DELTA)


@pytest.fixture(scope="module")
def jaw():
    """A Hertz contact below a sphere centred at ``center`` (the pad's face at z = 5 mm)."""
    center = np.array([0.0, 0.0, 5e-3 + R])
    return hertz_profile(R, DELTA, 1e6, 0.45, center=center), center


def test_equal_force_jaws_carry_the_reference_force(jaw):
    prof, _ = jaw
    coef = patch_coefficients(MU, R, DELTA, "hertz")
    rows = {
        "twice": {"profile": prof.with_pressures(2 * prof.pressures)},
        "cone": {"profile": None, "coefficients": coef},
    }
    jaws = equal_force_jaws(rows, prof, 3.0)
    assert list(jaws) == ["twice", "cone"]
    assert jaws["twice"]["kind"] == "profile"
    assert metrics.jaw_force(jaws["twice"]["profile"]) == pytest.approx(3.0, rel=1e-12)
    # the scale is uniform: the shape of the pressure field is the peer's
    np.testing.assert_allclose(
        jaws["twice"]["profile"].pressures / prof.pressures, 3.0 / metrics.jaw_force(prof), rtol=1e-12
    )
    cone = jaws["cone"]
    assert cone["kind"] == "cone" and cone["force"] == 3.0 and cone["coefficients"] is coef
    np.testing.assert_array_equal(cone["point"], prof.pressure_center)


def test_equal_force_margins_do_not_depend_on_the_peers_or_the_references_force(jaw):
    prof, center = jaw
    kw = {"seed": 0, "n_disturbances": 3, "steps": 8}
    rows = {
        "same": {"profile": prof},
        "twice": {"profile": prof.with_pressures(2 * prof.pressures)},
        "cone": {"profile": None, "coefficients": patch_coefficients(MU, R, DELTA, "hertz")},
    }
    truth, m = equal_force_margins(rows, prof, center, MU, **kw)
    assert list(m) == ["same", "twice", "cone"] and truth.shape == (3,) and (truth > 0).all()
    # the truth is the reference's own grasp against disturbances scaled by f_ref / 25 N
    f_ref = metrics.jaw_force(prof)
    own = grasp_margins(
        {"r": {"kind": "profile", "profile": prof}}, center, MU, scale=f_ref / DISTURBANCE_FORCE_N, **kw
    )["r"]
    assert truth.tolist() == own.tolist()
    assert m["same"].tolist() == truth.tolist()
    # a peer pressing twice as hard is compared at the reference's force: the same margins
    res = 2.0 ** (2 * np.log2(MARGIN_SPAN) / 2 ** kw["steps"])
    np.testing.assert_allclose(m["twice"], truth, rtol=res - 1)
    # a reference three times as strong: the disturbances and every jaw scale with it, and
    # friction is linear in the normal force — the same margins
    truth3, m3 = equal_force_margins(rows, prof.with_pressures(3 * prof.pressures), center, MU, **kw)
    np.testing.assert_allclose(truth3, truth, rtol=res - 1)
    np.testing.assert_allclose(m3["cone"], m["cone"], rtol=res - 1)
