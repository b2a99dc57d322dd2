"""Minimal work of the jaws (thesis §4.3.2.3, Eq. 4.4-4.6) and the minimal-force quality.

The grasp's minimal normal forces ``f_i`` (Eq. 4.4, :func:`~.resistance.min_grasp_force`
with ``objective="sum"``) press the object by ``d_i = f_i / s_i + ε`` at each contact
(Hooke's law with the object's stiffness ``s_i`` there; ε lets rigid regions,
``s_i = inf``, count), and the jaws do the work ``W = Σ_i f_i d_i`` (Eq. 4.5).  The
qualities normalise by a maximum chosen from physical data:
``q_work = 1 − W / W_max`` (Eq. 4.6), ``q_force = 1 − Σ f / f⊥max`` (§4.3.3.2).

W is evaluated at the forces that minimise ``Σ f`` — the thesis's algorithm — not
minimised itself: with unequal stiffness a different split of the forces could need
less work.  With every contact rigid, ``W = ε Σ f`` and ``q_work`` ranks grasps as
``q_force`` does.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import config
from .gws import check_contacts
from .resistance import CutStore, min_grasp_force
from .stiffness_map import check_stiffness

log = logging.getLogger(__name__)

__all__ = ["MinimalWork", "minimal_work", "q_force", "q_work", "work"]


def _eps(eps) -> float:
    e = config.DEFAULTS.work_eps if eps is None else eps
    if isinstance(e, (bool, np.bool_)) or not np.isscalar(e) or not (np.isfinite(e) and e >= 0):
        raise ValueError(
            f"eps must be a finite displacement >= 0 [m] (Eq. 4.5); got {e!r} — "
            f"None uses config.DEFAULTS.work_eps = {config.DEFAULTS.work_eps:g} m"
        )
    return float(e)


def _check_stiffness(stiffness, n: int) -> np.ndarray:
    return check_stiffness(
        stiffness,
        n,
        "contact",
        fix="evaluate a StiffnessMap at the contact points: smap(np.array([c.t for c in contacts]))",
    )


def _check_forces(forces) -> np.ndarray:
    f = np.asarray(forces, dtype=float)
    if f.ndim != 1:
        raise ValueError(f"forces must be (N,) normal forces [N]; got shape {f.shape}")
    bad = ~np.isfinite(f) | (f < 0)
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(
            f"forces must be finite and >= 0 [N]; got {f[k]} at contact {k} "
            "(an unresisted grasp has no forces: its work is inf, see minimal_work)"
        )
    return f


def displacements(forces, stiffness, eps: float | None = None) -> np.ndarray:
    """(N,) jaw displacements ``d_i = f_i / s_i + ε`` [m] (Eq. 4.5); ``s_i = inf`` gives ε.

    forces : (N,) float — normal forces [N], finite, >= 0.
    stiffness : (N,) float — object stiffness at each contact [N/m], > 0 or ``np.inf``.
    eps : ε [m], >= 0; None reads ``config.DEFAULTS.work_eps``.
    """
    f = _check_forces(forces)
    s = _check_stiffness(stiffness, len(f))
    return f / s + _eps(eps)


def work(forces, stiffness, eps: float | None = None) -> float:
    """``W = Σ_i f_i (f_i / s_i + ε)`` [J] (thesis Eq. 4.5).

    forces : (N,) float — normal forces [N], finite, >= 0.
    stiffness : (N,) float — object stiffness at each contact [N/m], > 0; ``np.inf``
        for a rigid contact (its displacement is ε).
    eps : ε [m], >= 0; None reads ``config.DEFAULTS.work_eps``.
    """
    f = _check_forces(forces)
    return float(f @ displacements(f, stiffness, eps))


def _quality(x, x_max, name: str, max_name: str):
    xm = x_max
    if isinstance(xm, (bool, np.bool_)) or not np.isscalar(xm) or not (np.isfinite(xm) and xm > 0):
        raise ValueError(
            f"{max_name} must be a finite number > 0 (the normaliser); got {xm!r} — "
            "fit it on training grasps with workbench.grasp.fit_normaliser"
        )
    a = np.asarray(x, dtype=float)
    bad = np.isnan(a) | (a < 0)
    if bad.any():
        raise ValueError(
            f"{name} must be >= 0 (np.inf for an unresisted grasp); got {a[bad].ravel()[:3].tolist()}"
        )
    q = 1.0 - a / float(xm)
    return float(q) if q.ndim == 0 else q


def q_work(W, W_max: float):
    """Minimal-work quality ``q_work = 1 − W / W_max`` (thesis Eq. 4.6).

    W : float or (n,) float — work [J], >= 0; ``np.inf`` (unresisted) gives ``-inf``.
    W_max : normaliser [J], > 0 (the thesis chose it from physical data, §4.3.3.2).

    Not clipped: ``W > W_max`` gives ``q < 0``, so the ranking of grasps is kept.
    Returns a float for a scalar ``W``, else an array of its shape.
    """
    return _quality(W, W_max, "W", "W_max")


def q_force(f_sum, f_max: float):
    """Minimal-force quality ``q_force = 1 − f⊥ / f⊥max`` (thesis §4.3.3.2).

    f_sum : float or (n,) float — minimal total normal force [N] (Eq. 4.4), >= 0;
        ``np.inf`` (unresisted) gives ``-inf``.
    f_max : normaliser [N], > 0 ("determined experimentally").

    Not clipped (as :func:`q_work`).  Returns a float for a scalar, else an array.
    """
    return _quality(f_sum, f_max, "f_sum", "f_max")


@dataclass(frozen=True)
class MinimalWork:
    """Work of the minimal grasp forces (thesis Eq. 4.4-4.5).

    f_sum : ``Σ f_i`` [N], the minimal total normal force; ``inf`` when unresisted.
    forces : (N,) per-contact normal forces [N] (NaN when unresisted).
    stiffness : (N,) stiffness used [N/m] (``inf``: rigid).
    displacements : (N,) ``d_i = f_i / s_i + ε`` [m] (NaN when unresisted).
    W : work [J]; ``inf`` when unresisted.
    eps : ε used [m].
    resisted : whether some forces resist ``w_ext``.
    solver, representation, fallbacks, converged : of the
        :class:`~.resistance.MinimalForce` answer (``converged`` False: cutting planes
        ran out and ``f_sum`` is a lower bound).
    """

    f_sum: float
    forces: np.ndarray
    stiffness: np.ndarray
    displacements: np.ndarray
    W: float
    eps: float
    resisted: bool
    solver: str
    representation: str
    fallbacks: tuple[str, ...] = ()
    converged: bool = True


def minimal_work(
    contacts,
    w_ext,
    mu: float,
    stiffness,
    *,
    eps: float | None = None,
    representation: str = "outer",
    cuts: CutStore | None = None,
) -> MinimalWork:
    """Minimal grasp forces against ``w_ext`` and the work they do (Eq. 4.4-4.5).

    contacts : list of N :class:`~.contacts.ContactSet` (one per jaw in the thesis:
        a 6DLS of each jaw's REACH profile).
    w_ext : (6,) disturbance wrench [N, N·m], object frame.
    mu : friction coefficient.
    stiffness : (N,) float — object stiffness at each contact [N/m], ``np.inf`` rigid
        (e.g. a :class:`~.stiffness_map.StiffnessMap` at the contacts' points).
    eps : ε of Eq. 4.5 [m]; None reads ``config.DEFAULTS.work_eps``.
    representation : "outer" (default: the thesis's ``C_outer``, Eq. 3.28, an LP) or
        "model" (the limit surfaces themselves: an ellipsoid as a second-order cone);
        passed to :func:`~.resistance.min_grasp_force` with ``objective="sum"`` (each
        contact's force free, ``Σ f`` minimised: Eq. 4.4 as published).
    cuts : cut store for quartic models under "model" (shared across calls).

    An unresisted ``w_ext`` gives ``f_sum = W = inf`` and ``resisted=False``.

    Notes
    -----
    * The balance is accepted to ``config.TOL.resist_rtol`` of the capacity at the
      contacts' *given* forces (``ContactSet.force``), so give them forces of the
      order of the answer: at 1e4 times the minimal force the band is ~10 % of it.
    * "outer" lies outside the ellipsoid, so its forces are lower bounds, loose at
      the usual M: on the elliptic-cylinder scene (0.3 kg, μ = 0.5) Σ f was 3.2 N at
      M = 100, 3.7 N at 200, 4.5 N at 1000 against 5.8 N for "model", with the two
      jaws' forces split unequally (which W then weighs by stiffness).
    * Stiffness is per contact: a jaw made of many contacts (REACH elements) would
      count each element's force in its own ``f (f / s + ε)``; pass one contact per
      jaw (the thesis: the 6DLS of the jaw's REACH profile).
    """
    e = _eps(eps)
    contacts = check_contacts(contacts)
    s = _check_stiffness(stiffness, len(contacts)).copy()
    mf = min_grasp_force(contacts, w_ext, mu, objective="sum", representation=representation, cuts=cuts)
    if not mf.feasible:
        log.debug("minimal work: w_ext is not resisted; W = inf")
        nan = np.full(len(s), np.nan)
        return MinimalWork(
            float("inf"),
            nan,
            s,
            nan.copy(),
            float("inf"),
            e,
            False,
            mf.solver,
            mf.representation,
            mf.fallbacks,
            mf.converged,
        )
    # the solver may return forces a rounding below 0
    f = np.maximum(np.asarray(mf.forces, dtype=float), 0.0)
    d = displacements(f, s, e)
    return MinimalWork(
        float(f.sum()),
        f,
        s,
        d,
        float(f @ d),
        e,
        True,
        mf.solver,
        mf.representation,
        mf.fallbacks,
        mf.converged,
    )
