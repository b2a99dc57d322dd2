"""Robustness that moves the gripper (6DFC §V-B.1; REACH; thesis Eq. 2.101 with the pose as
the uncertain parameter): N_r gripper poses sampled around the nominal one, the contact
recomputed at each, the quality the mean over the samples.

The sample ``T_k = T · [exp([ξ_k]×), t_k]`` perturbs the gripper in its own frame, with
``t_k ~ N(0, σ_t² I)`` [m] and ``ξ_k ~ N(0, σ_r² I)`` [rad] (a uniformly random axis; the
angle ``|ξ|`` scales with σ_r) — the construction of ipc-graspsim's ``GaussianPoseRV`` that
generated the REACH trials' perturbations; 6DFC states "a random 3D translation from a
zero-mean Gaussian with variance σ_r² and a uniformly random 3D rotation".  A sample whose pad
misses the object is a failed sample (quality 0).

:func:`~.robust.q_robust` is the other robustness: it moves the *contacts* already computed
(the profiles ride along rigidly) and perturbs μ, mass and centre of mass — no contact is
recomputed, so a pad that would slide off the object still holds there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

__all__ = ["PoseNoise", "pose_samples"]


@dataclass(frozen=True)
class PoseNoise:
    """Gripper-pose noise of pose robustness: ``n_samples`` (N_r), ``sigma_trans`` [m] and
    ``sigma_rot`` [rad] per axis; None takes ``config.DEFAULTS.pose_samples`` (10, 6DFC
    Fig. 3's best), ``pose_sigma_trans`` (0.003 m, 6DFC's σ_r) and ``pose_sigma_rot`` (0.003
    rad, 0.17°: ipc-graspsim's rotation σ; 6DFC gives no number)."""

    n_samples: int | None = None
    sigma_trans: float | None = None
    sigma_rot: float | None = None

    def resolved(self) -> PoseNoise:
        """This noise with the config's defaults filled in and every field checked."""
        from .. import config

        d = config.DEFAULTS
        n = d.pose_samples if self.n_samples is None else self.n_samples
        st = d.pose_sigma_trans if self.sigma_trans is None else self.sigma_trans
        sr = d.pose_sigma_rot if self.sigma_rot is None else self.sigma_rot
        return PoseNoise(int(n), float(st), float(sr))  # checked by __post_init__

    def __post_init__(self) -> None:
        # refuse a careless noise when it is made, not when it is first used; the one rule of a
        # pose noise (workbench.plausible), as Perturbation's
        from .. import config
        from ..plausible import check

        if self.n_samples is not None:
            config.check_value("pose_samples", self.n_samples, "PoseNoise.n_samples")
        if self.sigma_trans is not None:
            check("pose_noise_trans", self.sigma_trans, "PoseNoise.sigma_trans")
        if self.sigma_rot is not None:
            check("pose_noise_rot", self.sigma_rot, "PoseNoise.sigma_rot")


def check_pose(pose, what: str = "pose") -> np.ndarray:
    """``pose`` as a (4, 4) rigid transform [m], or a ValueError naming the mistake (the one rule
    of :func:`~workbench.units.check_rigid`: not 4×4, not a rotation, a translation in
    millimetres, a transposed matrix)."""
    from ..units import check_rigid

    return check_rigid(pose, what)


def pose_samples(pose, noise: PoseNoise | None = None, seed: int | np.random.Generator = 0) -> np.ndarray:
    """(N_r, 4, 4) gripper poses around ``pose`` (4, 4; the gripper in the object frame),
    perturbed in the gripper's frame (module docstring).  Same seed ⇒ same samples."""
    T = check_pose(pose)
    p = (PoseNoise() if noise is None else noise).resolved()
    from .robust import check_seed

    rng = np.random.default_rng(check_seed(seed))
    xi = rng.normal(0.0, p.sigma_rot, (p.n_samples, 3))
    t = rng.normal(0.0, p.sigma_trans, (p.n_samples, 3))
    D = np.tile(np.eye(4), (p.n_samples, 1, 1))
    D[:, :3, :3] = Rotation.from_rotvec(xi).as_matrix()
    D[:, :3, 3] = t
    return T @ D
