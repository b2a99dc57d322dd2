"""The REACH press's compiled passes (workbench/sources/_kernels.py) against NumPy references
(tests/naive.py), and the whole press against the NumPy-only algorithm it replaced: every
profile equal bit for bit, on meshes, pads, outlines, windows and approaches drawn at random."""

import numpy as np
import pytest
import trimesh
from naive import elements_may_touch, faces_may_overlap, frame_coordinates, front_most, front_surface
from scipy.spatial.transform import Rotation

from workbench.sources import reach
from workbench.sources._kernels import _elements_may_touch, _faces_may_overlap, _front_most
from workbench.sources.jaws import jaw_frame
from workbench.sources.pad_patch import PadPatch


def _frame(rng):
    a, e1, e2 = jaw_frame(rng.normal(size=3), rng.normal(size=3))
    return np.array([a, e1, e2])


def test_the_face_pass_is_the_reference_and_brackets_the_exact_test():
    rng = np.random.default_rng(0)
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.03)
    V, F = np.asarray(mesh.vertices), np.asarray(mesh.faces, np.int64)
    n_edge = 0
    for trial in range(40):
        fr, c = _frame(rng), rng.normal(0, 0.01, 3)
        lo = rng.uniform(-0.02, 0.0, 3)
        box = np.ravel(np.column_stack([lo, lo + rng.uniform(0.001, 0.02, 3)]))
        # the exact test of the press (coordinates by matrix products)
        rel = V - c
        uvz = np.column_stack([rel @ fr[1], rel @ fr[2], rel @ fr[0]])[F]  # (f, 3 vertices, 3)

        def exact_test(box, uvz=uvz):
            ok = np.ones(len(F), bool)
            for k in range(3):
                ok &= (uvz[:, :, k].min(1) <= box[2 * k + 1]) & (uvz[:, :, k].max(1) >= box[2 * k])
            return ok

        exact = exact_test(box)
        if trial % 2 and exact.any():  # a face touching the box's far side: at the pass's margin
            k = rng.integers(3)
            box[2 * k + 1] = max(uvz[rng.choice(np.flatnonzero(exact)), :, k].min(), box[2 * k])
            exact = exact_test(box)
        for tol in (0.0, 1e-9, 1e-4):
            got, sure = _faces_may_overlap(V, F, c, fr, box, tol)
            ref, ref_sure = faces_may_overlap(V, F, c, fr, box, tol)
            np.testing.assert_array_equal(got, ref)
            np.testing.assert_array_equal(sure, ref_sure)
            if tol > 0:  # beyond round-off: the pass brackets the exact test
                assert set(np.flatnonzero(exact)) <= set(got)
                assert exact[got[sure]].all()
            if tol == 1e-9:
                n_edge += int((~sure).sum())
    assert n_edge > 0  # the bounds through vertices left faces for the exact test to judge


def test_the_element_pass_is_the_reference_at_zero_margin_and_a_superset_of_the_exact_test():
    rng = np.random.default_rng(1)
    n = 3000
    cen = rng.uniform(-0.02, 0.02, (n, 3))
    nrm = rng.normal(size=(n, 3))
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    area = rng.uniform(0, 1e-6, n)
    area[::7] = 0.0
    for _ in range(20):
        fr, c = _frame(rng), rng.normal(0, 0.005, 3)
        rows = np.sort(rng.choice(n, 2000, replace=False)).astype(np.int64)
        box = np.array(
            [-0.01, 0.01, -0.015, 0.012, *((-0.005, 0.02) if rng.random() < 0.5 else (-np.inf, np.inf))]
        )
        got = _elements_may_touch(cen, nrm, area, rows, c, fr, box, -0.1, 0.0)
        np.testing.assert_array_equal(got, elements_may_touch(cen, nrm, area, rows, c, fr, box, -0.1, 0.0))
        rel = cen[rows] - c
        u, v, z = rel @ fr[1], rel @ fr[2], rel @ fr[0]
        exact = (area[rows] > 0) & (nrm[rows] @ fr[0] < -0.1) & (np.abs(u) <= 0.01)
        exact &= (v >= -0.015) & (v <= 0.012) & (z >= box[4]) & (z <= box[5])
        assert set(rows[exact]) <= set(_elements_may_touch(cen, nrm, area, rows, c, fr, box, -0.1, 1e-9))


@pytest.mark.parametrize("cell", [1e-3, 1e-7])  # a slot a bin; bins too many for slots (sorted runs)
def test_the_front_most_pass_is_the_reference(cell):
    rng = np.random.default_rng(2)
    for _ in range(10):
        n = 2000
        u, v = rng.uniform(-0.01, 0.01, n), rng.uniform(-0.02, 0.02, n)
        z = rng.uniform(0, 0.01, n)
        z[rng.integers(n, size=50)] = z[0]  # ties
        idx = np.sort(rng.choice(n, 1500, replace=False)).astype(np.int64)
        n_v = int(0.04 / cell) + 2
        got = _front_most(u, v, z, idx, -0.01, -0.02, cell, n_v, 2e-3)
        np.testing.assert_array_equal(got, front_most(u, v, z, idx, -0.01, -0.02, cell, n_v, 2e-3))
        assert got[idx].sum() < len(idx) if cell == 1e-3 else got[idx].all()


def test_frame_coordinates_are_the_reference_of_the_passes_arithmetic():
    # the references restate the passes' sums; here each against the frame's matrix product
    rng = np.random.default_rng(3)
    p, fr, c = rng.normal(size=(500, 3)), _frame(rng), rng.normal(size=3)
    rel = p - c
    np.testing.assert_allclose(frame_coordinates(p, c, fr), rel @ fr[[1, 2, 0]].T, rtol=0, atol=1e-15)


# ------------------------------------------------------------ the whole press, NumPy only


def _slow_patch(cen, normal, area, c, frame, pad, poly, window, filter_window, stiffness, max_edge):  # noqa: PLR0913 - a press's settings, flat
    """The front-most surface under the footprint, every element tested by NumPy."""
    visible, z = front_surface(cen, normal, area, c, frame, pad, poly, window, filter_window, max_edge, 0.1)
    if visible is None:
        return None
    return PadPatch(
        cen[visible], normal[visible], area[visible], z[visible], float(z[visible].min()), frame[0], stiffness
    )


def _slow_reach_profile(mesh, center, approach, up, pad, poly, press):
    """reach_profile by NumPy alone: the near faces by their vertices' boxes, refined afresh."""
    a, e1, e2 = jaw_frame(approach, up)
    c = np.asarray(center, float)
    (u_lo, v_lo), (u_hi, v_hi) = (
        ((-pad[0] / 2, -pad[1] / 2), (pad[0] / 2, pad[1] / 2))
        if poly is None
        else (
            poly.min(axis=0),
            poly.max(axis=0),
        )
    )
    filter_window = press.window is not None
    lo, hi = press.window if filter_window else (-press.depth_window, press.depth_window)
    me = press.max_edge
    rel = mesh.vertices - c
    fu, fv, fz = (rel @ e1)[mesh.faces], (rel @ e2)[mesh.faces], (rel @ a)[mesh.faces]
    near = (fu.min(1) <= u_hi + 2 * me) & (fu.max(1) >= u_lo - 2 * me)
    near &= (fv.min(1) <= v_hi + 2 * me) & (fv.max(1) >= v_lo - 2 * me)
    near &= (fz.min(1) <= hi) & (fz.max(1) >= lo)
    if not near.any():
        return None
    cen, normal, area, _ = reach._fine_faces(mesh.vertices, mesh.faces[near], me)
    patch = _slow_patch(
        cen, normal, area, c, (a, e1, e2), pad, poly, (lo, hi), filter_window, press.stiffness, me
    )
    return None if patch is None else patch.profile(press.closing)


def _meshes():
    cyl = trimesh.creation.cylinder(radius=0.02, height=0.08, sections=40)
    capsule = trimesh.creation.capsule(height=0.05, radius=0.02, count=[24, 24])
    ell = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    ell.apply_scale([0.02, 0.03, 0.045])
    return {
        "box": trimesh.creation.box((0.04, 0.03, 0.06)),
        "cylinder": cyl,
        "capsule": capsule,
        "ellipsoid": ell,
    }


@pytest.mark.parametrize("cached", [False, True])
def test_reach_profile_is_the_numpy_algorithm_bit_for_bit(cached):
    rng = np.random.default_rng(4)
    hexagon = 0.01 * np.column_stack(
        [np.cos(np.arange(6) * np.pi / 3), 1.5 * np.sin(np.arange(6) * np.pi / 3)]
    )
    compared = 0
    for name, mesh in _meshes().items():
        reach._FINE.clear()
        if cached:
            reach.fine_surface(mesh, 1e-3)
        for _ in range(6):
            approach = Rotation.random(random_state=rng).apply([0, 0, -1.0])
            center = mesh.bounds.mean(0) - approach * 0.05
            center = mesh.nearest.on_surface([center])[0][0] + rng.normal(0, 0.002, 3)
            for pad, poly in (((0.02, 0.04), None), ((0.008, 0.02), None), (None, hexagon)):
                # a deep press also compares the surfaces behind the first touch's
                for window, closing in ((None, 1e-3), ((-0.003, 0.01), 1e-3), (None, 6e-3)):
                    press = reach.WinklerPress(window=window, closing=closing)
                    try:
                        fast = reach.reach_profile(
                            mesh,
                            center,
                            approach,
                            (0, 0, 1),
                            pad=pad or (0.02, 0.04),
                            outline=poly,
                            press=press,
                        )
                    except ValueError:
                        fast = None
                    slow = _slow_reach_profile(mesh, center, approach, (0, 0, 1), pad, poly, press)
                    assert (fast is None) == (slow is None), name
                    if fast is not None:
                        compared += 1
                        for k in ("centers", "normals", "areas", "pressures"):
                            np.testing.assert_array_equal(getattr(fast, k), getattr(slow, k), err_msg=name)
    assert compared >= 100
