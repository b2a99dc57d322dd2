"""workbench.grasp.gws: GWS inclusions (L1 in Linf) and symmetry, the epsilon metric, force groups."""

from dataclasses import replace

import numpy as np
import pytest
from grasp_helpers import MU, A, F, antipodal

from workbench.grasp import (
    build_gws,
    gravity_wrench,
    gws_points,
    point_contact,
    resists,
    resists_lp,
    soft_point_contact,
)
from workbench.grasp.gws import WrenchHull


def _three_finger():
    pts = [np.array([np.cos(a), np.sin(a), 0.0]) * A for a in (0.0, 2.1, 4.0)]
    return [soft_point_contact(p, p / A + [0, 0, 0.2], F, 0.003, n_edges=6) for p in pts]


def test_l1_inside_linf_and_strictly_smaller():
    grasp = _three_finger()
    l1 = gws_points(grasp, MU, "l1")
    linf = build_gws(grasp, MU, "linf")
    assert linf.dim == 6
    assert linf.contains(l1, tol=1e-9).all()
    # and not the other way round: some Minkowski-sum points lie outside W_L1
    l1_hull = WrenchHull.from_points(l1)
    assert not l1_hull.contains(gws_points(grasp, MU, "linf")).all()
    # LP membership says the same for the union vertices
    assert all(resists_lp(grasp, -w, MU, "linf") for w in l1[::7])


def test_gws_of_mirror_symmetric_contacts_is_symmetric():
    grasp = antipodal(soft=0.004, n=8)
    hull = build_gws(grasp, MU)
    pts = gws_points(grasp, MU)
    # mirror x -> -x swaps the two contacts; forces reflect, torques are pseudovectors
    Mx = np.diag([-1.0, 1, 1, 1, -1, -1])
    My = np.diag([1.0, -1, 1, -1, 1, -1])
    for M in (Mx, My):
        assert hull.contains(pts @ M.T, tol=1e-9).all()
    # gravity up or down is resisted alike
    w = gravity_wrench(0.8, [0.0, 0.0, 0.0])
    assert bool(resists_lp(grasp, w, MU)) == bool(resists_lp(grasp, w * [1, 1, -1, 1, 1, -1], MU))


def test_epsilon_metric_of_a_symmetric_grasp():
    grasp = _three_finger()
    hull = build_gws(grasp, MU, torque_length=A)
    eps = hull.epsilon()
    assert eps > 0
    # the ball of radius ε is inside: random directions at 0.999 ε are members
    rng = np.random.default_rng(0)
    d = rng.normal(size=(200, 6))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    assert hull.contains(0.999 * eps * d).all()
    assert build_gws(antipodal(), MU).epsilon() == 0.0  # 5-dimensional GWS: no ball fits


def test_force_group_hull_matches_the_program():
    """The GWS of force-grouped contacts (one Minkowski block per group, at full force and
    at (1 − r)) holds exactly the wrenches the grouped program resists (inner vertices):
    two jaws of two point elements each, known forces, one reading per jaw."""
    jaws = []
    for side, g in ((1.0, "jaw-a"), (-1.0, "jaw-b")):
        for dz in (-0.01, 0.01):
            c = point_contact([side * A, 0, dz], [side, 0, 0], F / 2, n_edges=4)
            jaws.append(replace(c, cone=False, group=g))
    hull = build_gws(jaws, MU)
    rng = np.random.default_rng(5)
    W = np.c_[rng.normal(0, 0.25 * F, (300, 3)), rng.normal(0, 0.25 * F * A, (300, 3))]
    W[:, 0] *= 0.05  # along the grasp axis only the force mismatch (1 %) is reachable
    inside = hull.contains(-W)
    lp = np.array([bool(resists(jaws, w, MU, representation="inner")) for w in W])
    qp = np.array([bool(resists(jaws, w, MU)) for w in W])
    assert 20 < inside.sum() < 280
    assert (inside == lp).mean() >= 0.99 and (lp == qp).mean() >= 0.99  # boundary cases aside (measured: 1.0)
    with pytest.raises(ValueError, match="max_points"):
        gws_points(jaws, MU, max_points=100)
