"""Linearised limit surfaces (thesis §3.3.6, Eqs. 3.19–3.24).

Directions ``s`` are sampled on the hypercube surface ``‖s‖∞ = 1`` (Eq. 3.19)
or on the unit sphere, in normalised coordinates of the model's subspace.  For
a model homogeneous of degree ``d`` the ray ``γ s`` meets ``f = 1`` at
``γ = f(s)^(-1/d)`` exactly — no Newton iteration.  Inner constraints are the
denormalised vertices ``s^LS = ŝ^LS ∘ w_max`` (Eqs. 3.20–3.21); outer ones the
tangent half-spaces ``nᵀw <= nᵀs^LS`` with ``n`` the raw-coordinate gradient
(Eqs. 3.22–3.24), valid for any convex model.  A flat model (subspace of
dimension r < 6) adds the equalities ``cᵀ(w ⊘ scale) = 0`` as ± half-space pairs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..seeds import check_seed


@dataclass(frozen=True)
class Linearization:
    """``vertices`` (M, 6) raw wrenches on the model; for ``kind="outer"``
    also ``A`` (m, 6), ``b`` (m,) with ``A w <= b``."""

    kind: str
    vertices: np.ndarray
    A: np.ndarray | None = None
    b: np.ndarray | None = None

    # tol: relative to the largest offset; a vertex of the polytope tests inside whatever its last bits
    def contains(self, w: np.ndarray, tol: float = 1e-9) -> np.ndarray:
        """Outer: ``A w <= b + tol |b|``-membership of wrenches (N, 6)."""
        if self.A is None:
            raise ValueError("contains() needs the outer (half-space) linearisation")
        w = np.atleast_2d(w)
        return (w @ self.A.T <= self.b + tol * np.abs(self.b).max()).all(axis=1)


def sample_directions(M: int, dim: int, kind: str = "cube", seed: int = 0) -> np.ndarray:
    """(M, dim) directions on the hypercube surface (uniform over its faces) or
    on the unit sphere; seeded."""
    if M < 1:
        raise ValueError(f"M must be >= 1; got {M}")
    rng = np.random.default_rng(check_seed(seed))
    if kind == "sphere":
        s = rng.standard_normal((M, dim))
        return s / np.linalg.norm(s, axis=1, keepdims=True)
    if kind != "cube":
        raise ValueError(f"directions must be 'cube' or 'sphere'; got {kind!r}")
    s = rng.uniform(-1.0, 1.0, (M, dim))
    face = rng.integers(0, dim, M)
    s[np.arange(M), face] = rng.choice([-1.0, 1.0], M)
    return s


def surface_points(model, directions: np.ndarray) -> np.ndarray:
    """Normalised points ``ŝ = γ s`` on ``f = 1`` for directions (M, r) in
    subspace coordinates, ``γ = f(s)^(-1/d)`` (Eq. 3.19 in closed form)."""
    s = directions @ model.subspace.basis.T
    gamma = model._value_n(s) ** (-1.0 / model.degree)
    return gamma[:, None] * s


def linearize(
    model, M: int, kind: str = "inner", *, directions: str = "cube", seed: int = 0
) -> Linearization:
    """Inner vertices or outer half-spaces of a fitted model with M directions."""
    if kind not in ("inner", "outer"):
        raise ValueError(f"kind must be 'inner' or 'outer'; got {kind!r}")
    s_hat = surface_points(model, sample_directions(M, model.dim, directions, seed))
    vertices = s_hat * model.scale  # Eq. 3.20
    if kind == "inner":
        return Linearization("inner", vertices)
    g = model.gradient(vertices)  # raw-coordinate normal, Eq. 3.23 generalised
    n = g / np.linalg.norm(g, axis=1, keepdims=True)
    A, b = n, np.einsum("ij,ij->i", n, vertices)  # Eq. 3.24
    C = model.subspace.complement
    if C.shape[1]:
        flat = (C / model.scale[:, None]).T  # c^T (w / scale) = 0
        flat = flat / np.linalg.norm(flat, axis=1, keepdims=True)
        A = np.vstack([A, flat, -flat])
        b = np.concatenate([b, np.zeros(2 * len(flat))])
    if M < _BOUNDED_CHECK_BELOW:
        _check_bounded(A, b, M, model.dim)
    return Linearization("outer", vertices, A, b)


# below this many directions an outer polytope may be unbounded (its tangent planes' normals
# must positively span the subspace: at least dim + 1 of them, in no half-space), so it is
# checked by one LP per axis and sign; at the default M = 200 the cube's sampled directions
# span, and the check would be a cost on every grasp
_BOUNDED_CHECK_BELOW = 64


def _check_bounded(A: np.ndarray, b: np.ndarray, M: int, dim: int) -> None:
    """Refuse an outer polytope ``A w <= b`` that is unbounded along some axis: it would resist
    any load along it (a 6DFC with M = 1 held 100 N sideways with a 10 N grip)."""
    from scipy.optimize import linprog

    for k in range(A.shape[1]):
        for sign in (1.0, -1.0):
            c = np.zeros(A.shape[1])
            c[k] = -sign
            res = linprog(c, A_ub=A, b_ub=b, bounds=[(None, None)] * A.shape[1], method="highs")
            if res.status == 3:  # unbounded
                raise ValueError(
                    f"M = {M} outer directions leave the linearised limit surface open (unbounded "
                    f"along {'+' if sign > 0 else '-'}w_{k}): an outer polytope resists any load there — "
                    f"pass M >= {_BOUNDED_CHECK_BELOW} (the default is 200), or kind='inner'"
                )
