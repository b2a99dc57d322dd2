"""The grouped inputs of a grasp evaluation: what the grasp must resist (:class:`Task`), the
parallel jaws of an antipodal grasp (:class:`Jaws`), how the contact models judge it
(:class:`ModelOptions`) and how a gripper's contact is computed and judged (:class:`GripperOptions`).

:func:`~.evaluate.evaluate_grasp` takes a Task, Jaws and ModelOptions;
:func:`~.gripper_eval.evaluate_gripper` / :func:`~.gripper_eval.evaluate_models` /
:func:`~.gripper_eval.judge_contact` take the same Task (the gripper, a
:class:`~workbench.sources.gripper.Gripper`, stands for the jaws: force, pad, μ) and GripperOptions.
Each is a frozen value: numbers and tuples only, each field checked when it is made by the one
rule of its quantity (a careless input is refused where it is written, with the same message as
before).  The checks that need the object's mesh — a centre of mass inside the object, a mass for
its volume — run where the mesh is known, in the evaluation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..seeds import check_seed
from ..sources.jaws import check_direction, check_jaw_force, check_pad
from .gws import check_mu
from .models import check_model
from .pose_robust import PoseNoise
from .robust import Perturbation, check_com, check_mass, check_task_wrench

__all__ = ["GripperOptions", "Jaws", "ModelOptions", "Task", "check_down_direction"]


def _floats(v: Any) -> tuple[float, ...]:
    """An already-checked vector as a tuple of Python floats (the same float64 values)."""
    return tuple(np.asarray(v, dtype=float).ravel().tolist())


def check_down_direction(down) -> np.ndarray:
    """``down`` (3,), gravity's direction in the object frame, as a unit (3,) array; a ValueError
    unless it is a non-zero finite (3,) vector — the one rule of a task's gravity direction."""
    d = np.asarray(down, dtype=float)
    if d.shape != (3,) or not np.isfinite(d).all() or np.linalg.norm(d) == 0:
        raise ValueError(
            "down must be a non-zero (3,) gravity direction in the object frame; "
            f"got {np.asarray(down).tolist()}"
        )
    return d / np.linalg.norm(d)


@dataclass(frozen=True)
class Task:
    """What the grasp must resist: a wrench ``w_ext`` (6,) = ``[f; τ]`` [N, N·m] about the object
    origin, OR gravity on ``mass`` [kg] at ``com`` (3,) [m] along ``down`` (3,; gravity's direction
    in the object frame, −z unless given — e.g. a trial's :attr:`~workbench.sources.trials.TrialGrasp.down`).

    Exactly one of the two forms: ``Task(w_ext=...)`` or ``Task(mass=..., com=..., down=...)``.
    ``com`` may be left None for a gripper (:func:`~.gripper_eval.evaluate_models` takes the mesh's
    centre of mass); :func:`~.evaluate.evaluate_grasp` needs it given.  ``down`` is kept as given
    (not normalised); it does not apply to a given ``w_ext``.  Checked when made:
    ``w_ext`` by :func:`~.robust.check_task_wrench` (a load a gripper could hold; not the zero
    wrench, which leaves nothing to resist), ``mass`` by
    :func:`~.robust.check_mass`, ``com`` as three finite numbers (:func:`~.robust.check_com`; inside
    the object where the mesh is known), ``down`` by :func:`check_down_direction`.  Vectors are
    stored as tuples of floats.
    """

    w_ext: tuple[float, ...] | None = None
    mass: float | None = None
    com: tuple[float, ...] | None = None
    down: tuple[float, ...] = (0.0, 0.0, -1.0)

    def __post_init__(self) -> None:
        if self.w_ext is None and self.mass is None:
            raise ValueError("give the task as w_ext (6,) or as mass [kg] and com (3,) [m]")
        if self.w_ext is not None and (self.mass is not None or self.com is not None):
            raise ValueError("give the task either as w_ext or as mass and com, not both")
        if self.w_ext is not None:
            w = check_task_wrench(self.w_ext)
            if not np.any(w):  # every grasp "resists" nothing: a task left at its placeholder
                raise ValueError(
                    "w_ext is the zero wrench: there is nothing to resist — give the load, e.g. "
                    "Task(mass=0.2, com=..., down=(0, 0, -1)) for gravity, or w_ext=(0, 0, -1.96, 0, 0, 0)"
                )
            object.__setattr__(self, "w_ext", _floats(w))
        else:
            object.__setattr__(self, "mass", float(check_mass(self.mass)))
        if self.com is not None:
            object.__setattr__(self, "com", _floats(check_com(self.com)))
        check_down_direction(self.down)
        object.__setattr__(self, "down", _floats(self.down))


@dataclass(frozen=True)
class Jaws:
    """The parallel jaws of an antipodal grasp (:func:`~.evaluate.evaluate_grasp`).

    force : the force-sensor reading of *each* jaw along the grasp axis [N] (§4.1.3.2), checked
        by :func:`~workbench.sources.jaws.check_jaw_force`.
    pad : the jaw face ``(width, length)`` [m] (:func:`~workbench.sources.jaws.check_pad`): REACH's
        footprint, and for given profiles the bound of the check that each lies at its jaw (pass
        the FEM pad's ``(width, length)``).
    up : (3,) the jaws' length axis (REACH's; checked as a non-zero finite direction, stored as given).
    """

    force: float = 10.0
    pad: tuple[float, float] = (0.02, 0.04)
    up: tuple[float, ...] = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "force", check_jaw_force(self.force))
        check_pad(self.pad)
        object.__setattr__(self, "pad", _floats(self.pad))
        check_direction(self.up, "up", "the pad's length direction, not parallel to approach, e.g. (0, 0, 1)")
        object.__setattr__(self, "up", _floats(self.up))


@dataclass(frozen=True)
class ModelOptions:
    """How :func:`~.evaluate.evaluate_grasp` judges a grasp.

    model : one of :data:`~.models.MODELS`; mu : friction coefficient (:func:`~.gws.check_mu`).
    representation : "model" (default), "outer" or "inner" (see :func:`~.resistance.resists`,
        which checks it).
    min_force : also solve the minimal grasp force (same model, ``objective="scale"``).
    robust : a :class:`~.robust.Perturbation` to also compute ``q_robust`` (the contacts ride
        along; the gripper's pose robustness, which recomputes them, is :class:`GripperOptions`'),
        or None.
    seed : the contact models' and q_robust's sampler seed, an integer >= 0 (the same draw on every
        evaluation).
    """

    model: str = "6dls"
    mu: float = 0.5
    representation: str = "model"
    min_force: bool = True
    robust: Perturbation | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        check_model(self.model)
        object.__setattr__(self, "mu", check_mu(self.mu))  # "0.5" from a file is kept as 0.5
        if self.representation not in ("model", "outer", "inner"):
            raise ValueError(
                f"representation must be 'model', 'outer' or 'inner'; got {self.representation!r}"
            )
        if not isinstance(self.min_force, (bool, np.bool_)):
            raise ValueError(f"min_force must be True or False; got {self.min_force!r}")
        if self.robust is not None and not isinstance(self.robust, Perturbation):
            raise ValueError(
                "robust must be a Perturbation (q_robust: the contacts perturbed as computed) or None; "
                f"got {type(self.robust).__name__}"
                + (
                    " — a PoseNoise recomputes a gripper's contact: evaluate_gripper with "
                    "GripperOptions(robust=...)"
                    if isinstance(self.robust, PoseNoise)
                    else ""
                )
            )
        object.__setattr__(self, "seed", check_seed(self.seed, generator=False))


@dataclass(frozen=True)
class GripperOptions:
    """How :func:`~.gripper_eval.evaluate_gripper` / :func:`~.gripper_eval.evaluate_models` compute
    and judge a gripper's contact.

    mu : the pad's friction coefficient, or None: the gripper's own (``Gripper.mu``); checked by
        :func:`~workbench.sources.gripper.check_pad_mu` (0.3 given as 30 is a percentage).
    robust : a :class:`~.pose_robust.PoseNoise`: also recompute the contact at N_r perturbed poses
        (``q_pose``, ``p_held``); None: the nominal pose only.
    settle : True (default): the object free to settle between the pads (:mod:`~.settle`); False:
        each pad pressed alone at the pose as given.
    seed : the pose samples' and the contact models' seed, an integer >= 0.
    """

    mu: float | None = None
    robust: PoseNoise | None = None
    settle: bool = True
    seed: int = 0

    def __post_init__(self) -> None:
        if self.mu is not None:
            from ..sources.gripper import check_pad_mu

            check_pad_mu(self.mu)
        if self.robust is not None and not isinstance(self.robust, PoseNoise):
            raise ValueError(
                "robust must be a PoseNoise (the gripper's pose perturbed, its contact recomputed) or "
                f"None; got {type(self.robust).__name__}"
            )
        if not isinstance(self.settle, (bool, np.bool_)):
            raise ValueError(f"settle must be True or False; got {self.settle!r}")
        object.__setattr__(self, "seed", check_seed(self.seed, generator=False))
