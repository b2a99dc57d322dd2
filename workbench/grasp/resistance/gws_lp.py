"""GWS membership by one LP over the contacts' vertices (no hull): the LP entry point of
"is this wrench resisted?", deciding like every other (``config.TOL.resist_rtol``)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from ..gws import (
    NORMS,
    capacity_scaling,
    check_contacts,
    check_mu,
    check_resist_tol,
    check_wrench,
    vertex_blocks,
)
from .api import resists
from .result import Resistance

__all__ = ["resists_lp"]


def resists_lp(contacts, w_ext, mu: float, norm: str = "linf", tol: float | None = None):
    """Whether ``−w_ext`` lies in the GWS of the contacts' vertices, by an LP (no hull):
    a :class:`~workbench.grasp.resistance.Resistance` (truthy iff resisted).

    ``norm="linf"`` (Minkowski sum, Eq. 4.2) is :func:`~workbench.grasp.resistance.resists`
    with ``representation="inner"``: one weight vector per contact, its force in the
    contact's interval (:meth:`ContactSet.force_bounds`).  ``norm="l1"`` (union,
    Eq. 2.88): one simplex over the points of :func:`vertex_blocks`.  Both
    minimise the L1 residual ``‖D (Σ α v + w_ext)‖₁`` (HiGHS) and decide with
    ``tol`` (``config.TOL.resist_rtol``), like every other entry point.
    """
    if norm not in NORMS:
        raise ValueError(f"norm must be one of {NORMS}; got {norm!r}")
    if norm == "linf":
        return resists(contacts, w_ext, mu, representation="inner", tol=tol)
    w = check_wrench(w_ext)
    contacts = check_contacts(contacts)
    check_mu(mu)
    tol = check_resist_tol(tol)
    V = np.vstack(vertex_blocks(contacts, mu))  # the union of the contacts' sets
    D = capacity_scaling(V)
    n = len(V)
    A_eq = np.vstack([np.hstack([V.T * D[:, None], -np.eye(6), np.eye(6)]), np.r_[np.ones(n), np.zeros(12)]])
    res = linprog(
        np.r_[np.zeros(n), np.ones(12)],
        A_eq=sp.csr_matrix(A_eq),
        b_eq=np.r_[-w * D, 1.0],
        bounds=(0, None),
        method="highs",
    )
    if res.status != 0:
        raise RuntimeError(f"HiGHS failed on the L1-GWS membership LP: {res.message}")
    alpha = res.x[:n]
    return Resistance(
        bool(res.fun <= tol),
        float(res.fun),
        tol,
        "highs",
        "inner",
        "l1",
        (alpha @ V)[None],
        np.array([np.nan]),
    )
