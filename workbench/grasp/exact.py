"""Exact wrench resistance of contact profiles: no limit-surface model, no sampling bias.

The contact-wrench set of a profile pressed with force F is
``C = {F (μ w + ŵ⊥) : w ∈ W}`` with W the frictional wrench set of the
normalised profile, whose support function is known exactly through maximum
dissipation: ``max_{w∈W} d·w = d·w(ξ = −d)`` (the 6DFW kernel at one twist).
The convex hull of sampled 6DFWs (the "raw 6DFW" model) is an *inner*
approximation of W — a finite sample in 6D misses a lot — so the question
``−w_ext ∈ Σ_i G_i C_i`` is answered here by column generation:

1. LP over the current columns: ``min 1ᵀ(s⁺ + s⁻)`` s.t. ``Σ α v − s⁺ + s⁻ = −w``,
   one weight simplex per contact (HiGHS);
2. optimum 0: member (resisted).  Otherwise the equality duals ``y`` give the LP's
   separating direction; with the exact supports ``h_i(y)``, a positive gap
   ``−w·y − Σ_i h_i(y) > 0`` certifies non-membership; else the support points
   ``argmax_{c∈C_i} c·y`` join the columns and the LP is solved again.

This is the ground truth of the sensitivity experiment (issue 5 scope 7).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from ..profile import ContactProfile
from ..twists import sample_twists_thesis
from ..wrench import frictional_wrenches
from .contacts import contact_map
from .gws import check_wrench


class ExactContacts:
    """Profiles of one grasp (object frame, wrenches about each pressure centre)
    with their sampled starting columns (μ = 1, unit force)."""

    def __init__(self, profiles: list[ContactProfile], n_start: int = 200, seed: int = 0) -> None:
        if not profiles:
            raise ValueError("a grasp needs at least one contact profile")
        self.norm = [p.normalized() for p in profiles]
        self.F = np.array([p.F for p in profiles])
        self.G = [contact_map(np.eye(3), p.pressure_center) for p in profiles]
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
    tol: float = 1e-9,
    max_iter: int = 200,
) -> tuple[bool, int]:
    """Whether the profiles pressed with ``forces`` (default: their own F) resist
    ``w_ext`` with friction ``mu``: (answer, LP iterations)."""
    w = check_wrench(w_ext)
    F = contacts.F if forces is None else np.asarray(forces, float)
    N = len(F)
    cols = [list(s) for s in contacts.start]
    sf = float(np.max(F) * (1 + mu)) or 1.0
    D = np.r_[np.full(3, 1 / sf), np.full(3, 1 / (sf * 0.05))]  # 5 cm torque arm: N·m vs N
    target = -w * D
    for it in range(1, max_iter + 1):
        V = [(F[i] * (mu * np.array(cols[i]) + contacts.normal[i])) @ contacts.G[i].T * D for i in range(N)]
        sizes = [len(v) for v in V]
        n = sum(sizes)
        A = np.zeros((6 + N, n + 12))
        A[:6, :n] = np.vstack(V).T
        A[:6, n : n + 6] = -np.eye(6)
        A[:6, n + 6 :] = np.eye(6)
        s0 = 0
        for i, m in enumerate(sizes):
            A[6 + i, s0 : s0 + m] = 1.0
            s0 += m
        cost = np.r_[np.zeros(n), np.ones(12)]
        res = linprog(
            cost, A_eq=sp.csr_matrix(A), b_eq=np.r_[target, np.ones(N)], bounds=(0, None), method="highs"
        )
        if res.status != 0:
            raise RuntimeError(f"HiGHS failed in resists_exact: {res.message}")
        if res.fun <= tol * max(1.0, np.abs(target).max()):
            return True, it
        y = np.asarray(res.eqlin.marginals[:6])
        d = D * y  # raw-wrench direction of the scaled dual
        gap = target @ y
        new = []
        for i in range(N):
            wi = contacts.support(i, d)
            new.append(wi)
            gap -= (F[i] * (mu * wi + contacts.normal[i])) @ contacts.G[i].T @ d
        if gap > tol * max(1.0, np.abs(target).max()):
            return False, it  # separated by the exact support: certified outside
        for i in range(N):
            cols[i].append(new[i])
    raise RuntimeError(f"resists_exact did not converge in {max_iter} column-generation rounds")
