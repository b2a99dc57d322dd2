"""Ellipsoidal 6D limit surface ``f(x̂) = x̂ᵀ A_e x̂`` (thesis §3.3.4).

Two fitters on normalised wrenches, both inside the PCA subspace (so a planar
contact is fitted in 3D, never as a singular 6D problem):

* ``method="lsq"`` — Eq. 3.13: linear least squares on the ``r(r+1)/2``
  unique entries of ``A``.  An indefinite result (rare; noisy or too few
  wrenches) is projected to the PD cone and rescaled — reported as a fallback.
* ``method="sdp"`` — PSD-constrained least squares, Eq. 3.11 with ``A ⪰ 0``, a
  semidefinite program solved by the fits' own interior point (:mod:`.sos_ipm`, one r × r
  block; the default, ``config.DEFAULTS.ellipsoid_solver``) or a conic solver through cvxpy;
  ``alpha > 0`` adds Eq. 3.12's ``−α log det A`` (cvxpy solvers only).  The thesis
  needs that penalty to keep ``det A > 0`` when the wrenches span a subspace (planar
  contacts); here the PCA subspace already does, so the default is
  ``α = config.TOL.sdp_alpha_per_wrench·K = 0``.  Measured
  (``results/ls-fitting`` → ``sdp_log_det_effect``): ``α = 1e-6·K`` (our former
  default) changes Eq. 3.18 by < 1e-5, ``α >= 1e-3·K`` only raises the error;
  without it the fit *is* "lsq" whenever the least-squares matrix is positive
  definite (the constraint is inactive; returned directly, no conic solve — a
  solver on an ill-conditioned ellipsoid stopped 25× short on its largest
  eigenvalue), and the SDP is solved only when it is indefinite.  The K-term objective is
  compressed by a QR factorisation to ``‖R a - c‖²`` so the conic problem depends
  only on ``r``: the interior point's maps are built once per ``r``, the cvxpy problem once per
  ``(r, log-det or not)`` with Parameters and re-solved.  The optimum of an indefinite
  least-squares A lies on the cone's boundary (A singular); a solver returns a strictly
  positive-definite iterate near it, whose smallest eigenvalue is set by the solver's stopping
  rule — the interior point's ~1e-10, Clarabel's ~1e-8 (measured on grasp contacts,
  results/benchmarks/limit_surface.json) — at the same objective to ~1e-8 relative.  A cvxpy
  solver's iterate may land on or just past the boundary: an A whose smallest eigenvalue is in
  ``[-config.TOL.sdp_singular_rtol, 0]`` of its largest has the eigenvalues below
  ``ellipsoid_eig_floor`` of it raised to that (recorded in ``info["fallback"]``); one further from
  definite is a failed solve, answered by the projected least squares.

The returned 6×6 ``A_e`` is always positive definite: dropped directions get a
semi-axis ``config.TOL.flat_axis`` (the model is flat to that thickness).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Any

import numpy as np

from .. import config
from ..blas_threads import on_one_blas_thread
from .base import LimitSurfaceModel
from .normalize import prepare
from .sdp_solver import IPM, check_fit_solver

log = logging.getLogger(__name__)

#: incremented whenever a cvxpy ellipsoid problem is built (tests count it)
BUILD_COUNT = {"sdp": 0}
#: the solver recorded for a fit answered by least squares without a conic solve
LSTSQ = "numpy.linalg.lstsq"


@dataclass(frozen=True)
class EllipsoidLS(LimitSurfaceModel):
    """``A_e`` : (6, 6) PD matrix in normalised coordinates (Eq. 3.11)."""

    A_e: np.ndarray = None  # type: ignore[assignment]
    degree: int = 2

    def _value_n(self, x: np.ndarray) -> np.ndarray:
        # two operands: einsum's three-operand loop is several times slower (docs/decisions.md)
        return np.einsum("ni,ni->n", x @ self.A_e, x)

    def _gradient_n(self, x: np.ndarray) -> np.ndarray:
        return 2.0 * x @ self.A_e

    def _hessian_n(self, x: np.ndarray) -> np.ndarray:
        return np.broadcast_to(2.0 * self.A_e, (len(x), 6, 6))

    @property
    def A_raw(self) -> np.ndarray:
        """(6, 6) matrix of the model in raw wrench coordinates:
        ``f(w) = wᵀ S⁻¹ A_e S⁻¹ w`` with ``S = diag(scale)``."""
        inv = 1.0 / self.scale
        return self.A_e * inv[:, None] * inv[None, :]

    @cached_property
    def factor(self) -> np.ndarray:
        """(r, 6) ``Q`` with ``f(w) = ‖Q w‖²`` on the model's PCA subspace (raw wrenches):
        the second-order cone ``‖Q w‖ <= 1`` of the grasp programs.  The complement of
        the subspace is left out (``A_e`` gives it a large ``config.TOL.flat_axis`` penalty that
        must not enter a cone; grasp programs pin it with equality rows instead):
        ``f = yᵀ (Bᵀ A_e B) y`` with ``y = Bᵀ (w / scale)``.  Derived from immutable
        fields only (a cache, not state)."""
        B = self.subspace.basis
        lam, U = np.linalg.eigh(B.T @ self.A_e @ B)
        return (np.sqrt(np.clip(lam, 0.0, None))[:, None] * U.T) @ B.T / self.scale[None, :]


def _sym_design(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Design matrix of ``yᵀAy`` in the unique entries (i <= j) of A."""
    r = y.shape[1]
    iu, ju = np.triu_indices(r)
    phi = y[:, iu] * y[:, ju] * np.where(iu == ju, 1.0, 2.0)
    return phi, iu, ju


def _unpack(a: np.ndarray, iu: np.ndarray, ju: np.ndarray, r: int) -> np.ndarray:
    A = np.zeros((r, r))
    A[iu, ju] = a
    A[ju, iu] = a
    return A


def _embed(A_r: np.ndarray, sub) -> np.ndarray:
    """6×6 PD matrix: ``A_r`` on the subspace, ``1/flat²`` on its complement."""
    B, C = sub.basis, sub.complement
    return B @ A_r @ B.T + (C @ C.T) / config.TOL.flat_axis**2


def _floored(lam: np.ndarray, V: np.ndarray) -> np.ndarray:
    """(r, r) ``V diag(λ') Vᵀ`` of eigenpairs (lam (r,), V (r, r)), the eigenvalues below
    ``config.TOL.ellipsoid_eig_floor`` × the largest raised to it: positive definite."""
    return (V * np.maximum(lam, config.TOL.ellipsoid_eig_floor * max(lam.max(), 1e-300))) @ V.T


def _lsq(y: np.ndarray) -> tuple[np.ndarray, str | None]:
    phi, iu, ju = _sym_design(y)
    a, *_ = np.linalg.lstsq(phi, np.ones(len(y)), rcond=None)
    A = _unpack(a, iu, ju, y.shape[1])
    lam, V = np.linalg.eigh(A)
    if lam.min() > config.TOL.ellipsoid_eig_floor * lam.max() > 0:
        return A, None
    # projection to the PD cone, then the best scalar multiple (Σ (s f - 1)² min)
    A = _floored(lam, V)
    f = np.einsum("ni,ni->n", y @ A, y)
    return A * (f.sum() / (f @ f)), "indefinite least-squares A projected to the PD cone"


@lru_cache(maxsize=32)
def _sdp_problem(r: int, log_det: bool):
    """cvxpy problem of Eq. 3.11 with ``A ⪰ 0`` in r dims with Parameters (R, c,
    alpha); ``log_det``: with Eq. 3.12's ``−α log det A`` (exponential cones)."""
    import cvxpy as cp

    BUILD_COUNT["sdp"] += 1
    n_u = r * (r + 1) // 2
    iu, ju = np.triu_indices(r)
    # linear map unique entries -> full symmetric matrix (column-major vec)
    S = np.zeros((r * r, n_u))
    for k, (i, j) in enumerate(zip(iu, ju, strict=True)):
        S[i + r * j, k] = 1.0
        S[j + r * i, k] = 1.0
    a = cp.Variable(n_u)
    R = cp.Parameter((n_u, n_u))
    c = cp.Parameter(n_u)
    alpha = cp.Parameter(nonneg=True)
    A = cp.reshape(S @ a, (r, r), order="F")
    A = 0.5 * (A + A.T)  # symmetric by construction; makes the symmetry explicit to cvxpy
    objective = cp.sum_squares(R @ a - c) - (alpha * cp.log_det(A) if log_det else 0.0)
    prob = cp.Problem(cp.Minimize(objective), [A >> 0])
    return prob, a, R, c, alpha, iu, ju


@lru_cache(maxsize=8)
def _ipm_program(r: int):
    """The interior point's fixed maps of Eq. 3.11 in r dimensions (:class:`.sos_ipm.SosProgram`):
    ``svec A = P a`` for the unique entries a (``np.triu_indices`` order) — a scaled permutation,
    √2 on the off-diagonals — one r × r block and no antisymmetric one, started at ``A = I``."""
    import scipy.sparse as sp

    from .sos import svec_index
    from .sos_ipm import SosProgram

    iu, ju = np.triu_indices(r)
    i_s, j_s = svec_index(r)
    row = {(int(i), int(j)): k for k, (i, j) in enumerate(zip(i_s, j_s, strict=True))}
    rows = [row[int(i), int(j)] for i, j in zip(iu, ju, strict=True)]
    P = sp.csr_matrix((np.where(iu == ju, 1.0, np.sqrt(2.0)), (rows, np.arange(len(iu)))))
    return SosProgram(P, sp.csr_matrix((len(iu), 0)), r, 0, np.where(iu == ju, 1.0, 0.0))


def _solve_ipm(Rm: np.ndarray, c: np.ndarray, r: int) -> tuple[np.ndarray | None, str]:
    """Eq. 3.11 with ``A ⪰ 0`` by :func:`.sos_ipm.solve`: (A (r, r) or None, status)."""
    from .sos_ipm import solve

    res = solve(Rm, c, _ipm_program(r))
    if not res.ok:
        return None, res.status
    iu, ju = np.triu_indices(r)
    return _unpack(res.a, iu, ju, r), res.status


def _sdp(
    y: np.ndarray, solver: str | None, alpha: float | None, warm_start: bool = True
) -> tuple[np.ndarray, str | None, str]:
    """Eq. 3.11 (Eq. 3.12 with alpha > 0) on normalised wrenches y (K, r) by ``solver`` (checked,
    upper case; None: :func:`fit_ellipsoid`'s default): (A (r, r), what fell back or None, the
    solver whose answer A is)."""
    r = y.shape[1]
    alpha_v = config.TOL.sdp_alpha_per_wrench * len(y) if alpha is None else float(alpha)
    if not (np.isfinite(alpha_v) and alpha_v >= 0):
        raise ValueError(f"alpha (the log-det weight of Eq. 3.12) must be finite and >= 0; got {alpha_v}")
    if solver is None:  # the interior point has no log-det term
        solver = "CLARABEL" if alpha_v > 0 else config.DEFAULTS.ellipsoid_solver  # upper case
    if solver == IPM and alpha_v > 0:
        raise ValueError(
            f"the interior point (solver='IPM') solves Eq. 3.11 with A ⪰ 0 only; Eq. 3.12's log-det term "
            f"(alpha = {alpha_v:g}) needs a cvxpy solver: pass solver='CLARABEL', or alpha=0"
        )
    if alpha_v == 0:
        A, note = _lsq(y)
        if note is None:  # least squares is already PD: the constraint A ⪰ 0 is inactive,
            return A, None, LSTSQ  # so it is the exact optimum (a conic solver only approximates it)
    phi = _sym_design(y)[0]
    Q, Rm = np.linalg.qr(phi)
    c_val = Q.T @ np.ones(len(y))
    failed = ""
    if solver == IPM:
        A, status = _solve_ipm(Rm, c_val, r)
        if A is not None:
            return A, None if status == "optimal" else "SDP solved to reduced accuracy", IPM
        failed, solver = f"IPM: {status}; fell back to CLARABEL", "CLARABEL"  # its checked fallback
    note, A, ran = _sdp_cvxpy(Rm, c_val, y, solver, alpha_v, warm_start)
    return A, "; ".join(n for n in (failed, note) if n) or None, ran


def _sdp_cvxpy(
    Rm: np.ndarray, c_val: np.ndarray, y: np.ndarray, solver: str, alpha_v: float, warm_start: bool
) -> tuple[str, np.ndarray, str]:
    """Eq. 3.11 (Eq. 3.12 with ``alpha_v > 0``) through the cached cvxpy problem: (what fell back
    or "", A (r, r), the solver whose answer A is); a singular A (to ``sdp_singular_rtol``) keeps
    its answer, floored (:func:`_floored`); a solver that fails or returns an A further from
    definite falls back to least squares."""
    r = y.shape[1]
    prob, a, R, c, alpha_p, iu, ju = _sdp_problem(r, alpha_v > 0)
    R.value = Rm
    c.value = c_val
    alpha_p.value = alpha_v
    try:
        prob.solve(solver=solver, warm_start=warm_start)
    except Exception as exc:  # solver missing or numerical failure
        A, note = _lsq(y)
        return (
            f"SDP with {solver} failed ({type(exc).__name__}: {exc}); used least squares"
            + (f"; {note}" if note else ""),
            A,
            LSTSQ,
        )
    if prob.status not in ("optimal", "optimal_inaccurate") or a.value is None:
        A, note = _lsq(y)
        return f"SDP status {prob.status}; used least squares" + (f"; {note}" if note else ""), A, LSTSQ
    A = _unpack(a.value, iu, ju, r)
    lam, V = np.linalg.eigh(A)
    status = "" if prob.status == "optimal" else "SDP solved to reduced accuracy"
    if lam.min() <= 0 < lam.max() and lam.min() >= -config.TOL.sdp_singular_rtol * lam.max():
        # the optimum of an indefinite least squares is singular (on the cone's boundary), and the
        # solver's iterate may land on or just past it: its eigenvalues raised to the floor
        A = _floored(lam, V)
        floor = config.TOL.ellipsoid_eig_floor * lam.max()
        note = f"SDP's A singular (the optimum on the cone's boundary): eigenvalues raised to {floor:.3g}"
        return "; ".join(n for n in (status, note) if n), A, solver
    if lam.min() <= 0:
        A, note = _lsq(y)
        return "SDP returned an indefinite A; used least squares" + (f"; {note}" if note else ""), A, LSTSQ
    return status, A, solver


@on_one_blas_thread  # small matrices: a threaded BLAS waits for the cores others hold
def fit_ellipsoid(
    wrenches: Any,
    method: str = "lsq",
    *,
    w_max: Any = None,
    solver: str | None = None,
    alpha: float | None = None,
    warm_start: bool = False,
) -> EllipsoidLS:
    """Fit an ellipsoidal 6DLS to raw frictional wrenches (K, 6).

    w_max : optional (6,) exact maxima (e.g. :func:`workbench.w_max`); default
        the sampled maxima ``max_k |w_k|`` of Algorithm 1.
    method : "lsq" (Eq. 3.13) or "sdp" (PSD-constrained least squares; module docstring).
    solver : of "sdp": "IPM" (the fits' own interior point, :mod:`.sos_ipm`; Clarabel is its
        checked fallback) or a cvxpy conic solver with semidefinite support ("CLARABEL", "SCS");
        None: ``config.DEFAULTS.ellipsoid_solver`` (read at call time), or Clarabel when the
        log-det weight ``alpha`` is positive (the interior point has no such term).
    alpha : log-det weight of Eq. 3.12 for "sdp"; default
        ``config.TOL.sdp_alpha_per_wrench · K`` (0: the penalty is off).
    warm_start : let cvxpy reuse the previous "sdp" fit of the same size in this process;
        off by default so a fit does not depend on what the process fitted before (as
        :func:`~.quartic.fit_quartic`, where it was measured to change the result).
    The result's ``info`` names the method, solver, fallback (or None; a fallback is also
    logged as a warning) and time.  An unknown ``solver`` raises ValueError
    (:func:`~.sdp_solver.check_fit_solver`), as does "IPM" with ``alpha > 0``.
    """
    t0 = time.perf_counter()
    if method not in ("lsq", "sdp"):
        raise ValueError(f"method must be 'lsq' or 'sdp'; got {method!r}")
    if method == "lsq" and alpha is not None:  # one meaning per word: never silently ignored
        raise ValueError(
            f"alpha (Eq. 3.12's log-det weight, got {alpha!r}) belongs to method='sdp'; "
            "method='lsq' has no such term — use method='sdp' or drop alpha"
        )
    if solver is not None:  # a name is checked whichever method (it selects nothing for "lsq")
        solver = check_fit_solver(solver)
    W, wm, scale, x, sub = prepare(wrenches, w_max)
    r = sub.dim
    n_unknown = r * (r + 1) // 2
    if len(W) < n_unknown:
        raise ValueError(
            f"an ellipsoid in {r} dimensions has {n_unknown} unknowns but only {len(W)} wrenches "
            f"were given — sample at least {n_unknown} (the thesis uses 100-1,000)"
        )
    y = x @ sub.basis
    if method == "lsq":
        (A_r, fallback), ran = _lsq(y), LSTSQ
    else:
        A_r, fallback, ran = _sdp(y, solver, alpha, warm_start)
    if fallback:
        log.warning("%s ellipsoid fit (%d wrenches, dim %d): %s", method, len(W), r, fallback)
    info = {
        "model": "ellipsoid",
        "method": method,
        # the solver whose answer the fit is: an "sdp" fit whose least-squares A is PD needs no
        # conic solve; a fallback to least squares is recorded as such
        "solver": ran,
        "fallback": fallback,
        "dim": r,
        "n_wrenches": len(W),
        "fit_time_s": time.perf_counter() - t0,
    }
    return EllipsoidLS(wm, scale, sub, info, A_e=_embed(A_r, sub))
