"""Manipulation tasks as 6D gravity wrenches at poses along the trajectory (thesis §4.3.3.3).

"Vertical lifting" holds the object upright against gravity: one pose.  "Lifting and
90° rotation" carries it while the gripper turns it by 90° about the grasp axis: the
trajectory is discretised into three poses, 0°, 45° and 90°, and in the object frame
gravity turns the other way about that axis.  A grasp's quality for a task is its
lowest quality over the poses (§4.3.3.3).

:func:`lever_disturbances` draws the §4.1.3.1 kind of task instead: weights hung at random
lever arms from an object grasped along x.
"""

from __future__ import annotations

import numpy as np

from ..plausible import check
from ..seeds import check_seed
from .robust import G_ACC, cross3, gravity_wrench

#: task -> rotation angles [deg] about the grasp axis of its poses
TASKS = {"vertical_lifting": (0.0,), "lift_and_rotate": (0.0, 45.0, 90.0)}


def task_wrenches(task: str, mass: float, com, axis) -> np.ndarray:
    """(k, 6) gravity wrenches in the object frame, about its origin, one per pose of ``task``.

    mass : kg; com : (3,) centre of mass [m] (both checked as in
    :func:`~.robust.gravity_wrench`: grams and millimetres are refused); axis : (3,) the
    grasp axis (rotation axis of "lift_and_rotate"; need not be unit).
    """
    if task not in TASKS:
        raise ValueError(f"task must be one of {tuple(TASKS)}; got {task!r}")
    a = np.asarray(axis, float)
    if a.shape != (3,) or not np.isfinite(a).all() or np.linalg.norm(a) == 0:
        raise ValueError(f"axis must be a non-zero (3,) direction; got {axis!r}")
    a = a / np.linalg.norm(a)
    # object turned by +θ about the axis in the world: world gravity seen in the object frame
    # is g turned by −θ — Rodrigues' formula on the one vector (scipy's Rotation costs a
    # noticeable share of the minimal-work metric's budget per grasp: docs/decisions.md)
    angles = -np.radians(np.asarray(TASKS[task]))[:, None]
    g = np.array([0.0, 0.0, -1.0])
    a_x_g = np.array([-a[1], a[0], 0.0])  # a × (0, 0, −1)
    down = g * np.cos(angles) + a_x_g * np.sin(angles) + a * (a @ g) * (1.0 - np.cos(angles))
    w0 = gravity_wrench(mass, com, down[0])  # its checks of mass and com, once
    if len(down) == 1:
        return w0[None]
    f = mass * G_ACC * down / np.linalg.norm(down, axis=1, keepdims=True)
    return np.concatenate([f, cross3(np.asarray(com, float), f)], axis=1)


__all__ = ["TASKS", "lever_disturbances", "task_wrenches"]


def _check_weight_range(weight_range) -> tuple[float, float]:
    """``(lo, hi)`` [N] of ``weight_range``: two plausible weights with ``lo <= hi``."""
    if isinstance(weight_range, (str, bytes)) or np.ndim(weight_range) != 1 or len(weight_range) != 2:
        raise ValueError(
            f"weight_range must be (lo, hi), two weights m g [N] with lo <= hi, e.g. (1.0, 14.0); "
            f"got {weight_range!r}"
        )
    lo, hi = (check("weight", v, f"weight_range[{i}] [N]") for i, v in enumerate(weight_range))
    if lo > hi:
        raise ValueError(
            f"weight_range must be (lo, hi) with lo <= hi [N]; got ({lo!r}, {hi!r}): the ends are "
            f"swapped — pass ({hi!r}, {lo!r})"
        )
    return lo, hi


def lever_disturbances(
    rng: int | np.random.Generator,
    n: int,
    weight_range=(1.0, 14.0),
    lever_x: float = 0.06,
    lever_z: float = 0.08,
) -> np.ndarray:
    """(n, 6) disturbances of the thesis's §4.1.3.1 kind for the elliptic-cylinder grasp
    (:func:`workbench.sources.scenes.elliptic_cylinder_grasp`, grasp axis x): weights
    ``m g`` in ``weight_range`` [N] (along −y) hung at lever arms ``|r_x| <= lever_x``,
    ``|r_z| <= lever_z`` [m] (``τ_x = r_z m g``, ``τ_z = −r_x m g``), plus small f_z, τ_y
    noise; nothing along the grasp axis x, which those setups never load and a planar
    3DLS cannot resist by construction (§4.1.3.4).

    ``lever_x``/``lever_z`` are judged by the plausible "lever" range and the ends of
    ``weight_range`` by the "weight" range (:func:`workbench.plausible.check`, the rule of the
    sensitivity experiment's keys of the same names: 60 is "probably in millimetres", 1400 in
    grams-force); a ``weight_range`` whose ends are swapped is refused, not left to numpy.
    ``rng`` : a ``numpy.random.Generator`` (drawn from) or an int seed >= 0
    (:func:`workbench.seeds.check_seed`)."""
    rng = np.random.default_rng(check_seed(rng, "rng"))
    lo, hi = _check_weight_range(weight_range)
    check("lever", lever_x, "lever_x [m]")
    check("lever", lever_z, "lever_z [m]")
    mg = rng.uniform(lo, hi, n)
    rx = rng.uniform(-lever_x, lever_x, n)
    rz = rng.uniform(-lever_z, lever_z, n)
    w = np.zeros((n, 6))
    w[:, 1] = -mg
    w[:, 3] = rz * mg
    w[:, 5] = -rx * mg
    return w + rng.normal(0.0, 1.0, (n, 6)) * [0.0, 0.3, 0.3, 0.003, 0.003, 0.003]
