"""Exact wrench resistance of contact profiles: no limit-surface model, no sampling bias.

The contact-wrench set of a profile pressed with force F is
``C = {F (μ w + ŵ⊥) : w ∈ W}`` with W the frictional wrench set of the
normalised profile, whose support function is known exactly through maximum
dissipation: ``max_{w∈W} d·w = d·w(ξ = −d)`` (the 6DFW kernel at one twist).
The convex hull of sampled 6DFWs (the "raw 6DFW" model) is an *inner*
approximation of W — a finite sample in 6D misses a lot — so the question
``−w_ext ∈ Σ_i G_i C_i`` is answered here by column generation:

1. LP over the current columns: ``min 1ᵀ(s⁺ + s⁻)`` s.t. ``Σ α v − s⁺ + s⁻ = −w``,
   one weight simplex per contact (HiGHS: :func:`~.resistance.solvers.highs_lp`);
2. optimum 0: member (resisted).  Otherwise the equality duals ``y`` give the LP's
   separating direction; with the exact supports ``h_i(y)``, a positive gap
   ``−w·y − Σ_i h_i(y) > 0`` certifies non-membership; else the support points
   ``argmax_{c∈C_i} c·y`` join the columns and the LP is solved again.

This is the ground truth of the sensitivity experiment.
"""

from __future__ import annotations

import numpy as np

from ..profile import ContactProfile
from ..twists import sample_twists_thesis
from ..wrench import frictional_wrenches
from .contacts import contact_map
from .gws import check_wrench
from .resistance.solvers import highs_lp


class ExactContacts:
    """Profiles of one grasp (object frame, wrenches about each pressure centre)
    with their sampled starting columns (μ = 1, unit force)."""

    def __init__(self, profiles: list[ContactProfile], n_start: int = 200, seed: int = 0) -> None:
        if not profiles:
            raise ValueError("a grasp needs at least one contact profile")
        self.norm = [p.normalized() for p in profiles]
        self.F = np.array([p.F for p in profiles])
        self.G = [contact_map(np.eye(3), p.pressure_center) for p in profiles]
        #: largest contact lever arm [m]: the torque floor of the capacity scaling
        self.arm = max(float(np.linalg.norm(p.pressure_center)) for p in profiles)
        self.normal = [p.normal_wrench / p.F for p in profiles]
        self.start = [
            frictional_wrenches(q, sample_twists_thesis(n_start // 2, q, seed), 1.0) for q in self.norm
        ]

    def support(self, i: int, d: np.ndarray) -> np.ndarray:
        """Frictional wrench (μ = 1, unit force, frame C) maximising ``(G_i w)·d``."""
        e = self.G[i].T @ d
        return frictional_wrenches(self.norm[i], (-e)[None, :], 1.0)[0]


def resists_exact(
    contacts: ExactContacts,
    w_ext,
    mu: float,
    forces=None,
    *,
    tol: float | None = None,
    force_rtol: float | None = None,
    max_iter: int = 200,
) -> tuple[bool, int]:
    """Whether the profiles pressed with ``forces`` (default: their own F) resist
    ``w_ext`` with friction ``mu``: (answer, LP iterations).

    Same meaning of "resisted" as :func:`~workbench.grasp.resistance.resists`: each
    force lies in the sensor interval ``[F(1 − r), F]`` (``force_rtol``, default
    ``config.TOL.known_force_rtol``), the residual is scaled by the grasp's capacity
    (largest contact force and torque of the starting columns, the torque floored at
    the force times the largest lever arm, as in the resistance program) and compared
    with ``tol`` (``config.TOL.resist_rtol``).
    """
    from .. import config
    from .gws import capacity_scaling, check_mu, check_resist_tol

    w = check_wrench(w_ext)
    check_mu(mu)
    tol = check_resist_tol(tol)
    r = (
        config.TOL.known_force_rtol
        if force_rtol is None
        else config.check_value("known_force_rtol", force_rtol, "force_rtol")
    )
    F = contacts.F if forces is None else np.asarray(forces, float)
    N = len(F)
    lo, hi = F * (1 - r), F
    # each contact's columns (its wrenches, μ = 1, unit force) as an array grown by one row a
    # round (one copy a round, where turning a list of rows into an array every round was slower;
    # the same rows, the same bits)
    cols = [np.array(s, dtype=float) for s in contacts.start]
    # unit-force columns u = μ w + ŵ⊥ in the object frame; weights α in newtons
    D = capacity_scaling(
        np.vstack([(F[i] * (mu * cols[i] + contacts.normal[i])) @ contacts.G[i].T for i in range(N)]),
        contacts.arm,
    )
    target = -w * D
    for it in range(1, max_iter + 1):
        U = [((mu * cols[i] + contacts.normal[i]) @ contacts.G[i].T * D) * F[i] for i in range(N)]
        sizes = [len(u) for u in U]
        n = sum(sizes)
        A = np.zeros((6, n + 12))
        A[:6, :n] = np.vstack(U).T
        A[:6, n : n + 6] = -np.eye(6)
        A[:6, n + 6 :] = np.eye(6)
        # Σ α_i ∈ [lo_i, hi_i] / F_i (α in units of F_i)
        B = np.zeros((2 * N, n + 12))
        s0 = 0
        for i, m in enumerate(sizes):
            B[i, s0 : s0 + m] = 1.0
            B[N + i, s0 : s0 + m] = -1.0
            s0 += m
        out = highs_lp(
            np.r_[np.zeros(n), np.ones(12)],
            np.vstack([A, B]),
            np.r_[target, np.full(2 * N, -np.inf)],
            np.r_[target, hi / F, -lo / F],
            np.zeros(n + 12),
            np.full(n + 12, np.inf),
        )
        if out is None:
            raise RuntimeError("HiGHS failed in resists_exact (no optimal solution of the column LP)")
        _, duals, fun = out
        if fun <= tol:
            return True, it
        y = duals[:6]
        d = D * y  # raw-wrench direction of the scaled dual
        gap = target @ y
        new = []
        for i in range(N):
            wi = contacts.support(i, d)
            new.append(wi)
            h = (mu * wi + contacts.normal[i]) @ contacts.G[i].T @ d  # support at unit force
            gap -= max(lo[i] * h, hi[i] * h)
        if gap > tol:
            return False, it  # separated by the exact support: certified outside
        for i in range(N):
            cols[i] = np.vstack([cols[i], new[i]])
    raise RuntimeError(f"resists_exact did not converge in {max_iter} column-generation rounds")
