"""workbench.grasp.exact: resistance by column generation on the exact support."""

import numpy as np
from grasp_helpers import MU

from workbench import config
from workbench.grasp import resists_lp


def _disc(R=0.01, x=0.03, n_r=12, n_t=36, p=1e4, outward=1.0):
    """Flat disc contact in the plane x = ±x0 (normal ±x outward), uniform pressure."""
    from workbench.profile import ContactProfile

    r_edges = np.linspace(0, R, n_r + 1)
    rc = 0.5 * (r_edges[1:] + r_edges[:-1])
    th = (np.arange(n_t) + 0.5) * 2 * np.pi / n_t
    Rr, Th = np.meshgrid(rc, th, indexing="ij")
    area = (np.pi * (r_edges[1:] ** 2 - r_edges[:-1] ** 2) / n_t)[:, None] * np.ones(n_t)
    centers = np.column_stack(
        [np.full(Rr.size, outward * x), (Rr * np.cos(Th)).ravel(), (Rr * np.sin(Th)).ravel()]
    )
    normals = np.tile([outward, 0.0, 0.0], (Rr.size, 1))
    return ContactProfile(centers, normals, area.ravel(), np.full(Rr.size, p))


def test_exact_resistance_of_two_flat_discs():
    """Column generation with the exact support: the friction force limit 2μF and the
    torsion limit 2μ Σ p a |r| of the discretised discs, to 10x the resistance tolerance
    (config.TOL.resist_rtol) — no polygon, no sampling."""
    from workbench.grasp.exact import ExactContacts, resists_exact

    discs = [_disc(), _disc(outward=-1.0)]
    ex = ExactContacts(discs, n_start=60)
    Fd = discs[0].F
    torsion = MU * float((discs[0].forces * np.linalg.norm(discs[0].centers[:, 1:], axis=1)).sum())
    band = 10 * config.TOL.resist_rtol
    for factor, expect in ((1 - band, True), (1 + band, False)):
        assert resists_exact(ex, np.array([0, 0, -factor * 2 * MU * Fd, 0, 0, 0]), MU)[0] == expect
        assert resists_exact(ex, np.array([0, 0, 0, factor * 2 * torsion, 0, 0]), MU)[0] == expect
    # the sampled 6DFW hull is an inner approximation of the same set
    from workbench.grasp.models import ModelParameters, contact_sets

    rng = np.random.default_rng(2)
    W = rng.normal(size=(40, 6)) * np.r_[np.full(3, 0.8 * MU * Fd), np.full(3, 1.2 * torsion)]
    W[:, 0] = 0.0  # nothing along the grasp axis
    hull = [c for d in discs for c in contact_sets(d, "6dfw", ModelParameters(n_wrenches=300))]
    dense = np.array([bool(resists_lp(hull, w, MU)) for w in W])
    exact = np.array([resists_exact(ex, w, MU)[0] for w in W])
    assert (exact | ~dense).all() and 0 < exact.mean() < 1
