"""Robust wrench resistance ``q_robust`` (thesis Eq. 2.101, §2.5.3.2; Mahler et al.).

``q_robust = (1/K) Σ R_i``: the fraction of K Monte-Carlo samples in which the
grasp still resists the (perturbed) gravity wrench.  Perturbed per sample:
the grasp pose (a rigid motion of all contact frames about the object origin:
rotation by a random axis–angle with σ_rot, translation with σ_trans — the
profiles ride along with the jaws; re-simulating the contact at the new pose is
the expensive exact alternative), the friction coefficient (relative σ_mu), the
mass (relative σ_mass) and the centre of mass (σ_com).  All samples are drawn
at once from one seeded generator (same seed ⇒ same q_robust).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .gws import check_contacts, resists_lp
from .qp import resists, wrench_resistance

G_ACC = 9.81  # m/s²


@dataclass(frozen=True)
class Perturbation:
    """Standard deviations of the Monte-Carlo perturbations (0 switches one off)."""

    n_samples: int = 100  # N_r
    sigma_trans: float = 0.002  # m, grasp-pose translation (σ_r of the 6DFC paper, position part)
    sigma_rot: float = 0.05  # rad, grasp-pose rotation
    sigma_mu: float = 0.1  # relative
    sigma_mass: float = 0.1  # relative
    sigma_com: float = 0.002  # m


def gravity_wrench(mass: float, com, down=(0.0, 0.0, -1.0)) -> np.ndarray:
    """(6,) gravity wrench about the object origin: ``[m g d; com × m g d]``."""
    f = mass * G_ACC * np.asarray(down, float)
    return np.concatenate([f, np.cross(np.asarray(com, float), f)])


def rotation_from_vector(v: np.ndarray) -> np.ndarray:
    """(…, 3, 3) rotation matrices of axis–angle vectors (…, 3) (Rodrigues)."""
    v = np.asarray(v, float)
    th = np.linalg.norm(v, axis=-1, keepdims=True)
    k = np.divide(v, th, out=np.zeros_like(v), where=th > 0)
    K = np.zeros((*v.shape[:-1], 3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    K = K - np.swapaxes(K, -1, -2)
    s, c = np.sin(th)[..., None], np.cos(th)[..., None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def q_robust(
    contacts,
    mu: float,
    mass: float,
    com,
    perturbation: Perturbation = Perturbation(),
    *,
    seed: int | np.random.Generator = 0,
    method: str = "lp",
    w_ext=None,
) -> float:
    """Eq. (2.101) for the task "hold against gravity" (vertical lifting).

    w_ext : a fixed disturbance (6,) to resist instead of the gravity wrench of
        ``mass`` at ``com`` (then σ_mass and σ_com do not apply).
    method : "lp" (vertex LP), "qp" (:func:`wrench_resistance`) or "auto" (:func:`resists`:
        the QP where every contact has half-spaces, the LP otherwise).
    """
    contacts = check_contacts(contacts)
    if w_ext is None and not (np.isfinite(mass) and mass > 0):
        raise ValueError(f"mass must be > 0 [kg]; got {mass}")
    p = perturbation
    if p.n_samples < 1:
        raise ValueError(f"n_samples must be >= 1; got {p.n_samples}")
    predict = {
        "lp": resists_lp,
        "qp": lambda cs, w, m: wrench_resistance(cs, w, m)[0],
        "auto": resists,
    }.get(method)
    if predict is None:
        raise ValueError(f"method must be 'lp', 'qp' or 'auto'; got {method!r}")
    rng = np.random.default_rng(seed)
    K = p.n_samples
    Rs = rotation_from_vector(rng.normal(0.0, p.sigma_rot, (K, 3)))
    ts = rng.normal(0.0, p.sigma_trans, (K, 3))
    mus = mu * np.clip(1 + rng.normal(0.0, p.sigma_mu, K), 0.0, None)
    masses = mass * np.clip(1 + rng.normal(0.0, p.sigma_mass, K), 1e-6, None)
    coms = np.asarray(com, float) + rng.normal(0.0, p.sigma_com, (K, 3))
    ok = 0
    for i in range(K):
        moved = [c.moved(Rs[i], ts[i]) for c in contacts]
        w = gravity_wrench(masses[i], coms[i]) if w_ext is None else w_ext
        ok += predict(moved, w, mus[i])
    return ok / K
