"""What a grasp-resistance question returns: the answer and how it was reached."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Resistance:
    """Answer to "does the grasp resist ``w_ext``?" (thesis Eq. 2.100).

    resisted : ``residual <= tol``; the object is truthy iff resisted, so
        ``if resists(...)`` reads as before.
    residual : smallest ``‖D (Σ_i G_i c_i + w_ext)‖`` over the contact model, D the
        capacity scaling (forces / largest contact force, torques / largest contact
        torque), in the norm ``norm`` its solver minimised ("l2": QP/SOCP, "l1": LP).
    tol : the threshold used (``config.TOL.resist_rtol`` unless overridden).
    solver : the solver whose answer decided ("quadprog", "daqp", "clarabel", "highs").
    representation : "model" (limit surfaces themselves), "outer" or "inner".
    contact_wrenches : (N, 6) object-frame contact wrenches at the optimum.
    forces : (N,) normal forces at the optimum [N].
    cut_rounds : cutting-plane rounds (quartic models; 0 otherwise).
    fallbacks : what did not go as planned, in order (also logged); empty when the
        first route answered.
    """

    resisted: bool
    residual: float
    tol: float
    solver: str
    representation: str
    norm: str
    contact_wrenches: np.ndarray
    forces: np.ndarray
    cut_rounds: int = 0
    fallbacks: tuple[str, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.resisted)


@dataclass(frozen=True)
class MinimalForce:
    """Smallest grasp force that resists ``w_ext`` (thesis Eq. 4.4).

    total : ``Σ_i f_i`` [N] (``inf`` when no force resists).
    forces : (N,) per-contact normal forces [N] (NaN when infeasible).
    scale : for ``objective="scale"``, the factor on every contact's current force
        (``contacts[i].force * scale``: the jaws keep their force ratio, as a
        parallel-jaw gripper squeezing with one grasp force does); ``inf`` when no force
        resists, NaN for "sum".
    objective : "scale" or "sum" (independent contact forces, Eq. 4.4 as published).
    solver, representation, cut_rounds, fallbacks : as in :class:`Resistance`.
    converged : False when the cutting planes ran out (the value is then a lower bound).
    """

    total: float
    forces: np.ndarray
    scale: float
    objective: str
    solver: str
    representation: str
    cut_rounds: int = 0
    fallbacks: tuple[str, ...] = ()
    converged: bool = True

    @property
    def feasible(self) -> bool:
        return bool(np.isfinite(self.total))
