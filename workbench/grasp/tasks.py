"""Manipulation tasks as 6D gravity wrenches at poses along the trajectory (thesis §4.3.3.3).

"Vertical lifting" holds the object upright against gravity: one pose.  "Lifting and
90° rotation" carries it while the gripper turns it by 90° about the grasp axis: the
trajectory is discretised into three poses, 0°, 45° and 90°, and in the object frame
gravity turns the other way about that axis.  A grasp's quality for a task is its
lowest quality over the poses (§4.3.3.3).
"""

from __future__ import annotations

import numpy as np

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
    # is g turned by −θ — Rodrigues' formula on the one vector (scipy's Rotation costs 0.2 ms
    # a call, a twentieth of the minimal-work metric's budget per grasp)
    angles = -np.radians(np.asarray(TASKS[task]))[:, None]
    g = np.array([0.0, 0.0, -1.0])
    a_x_g = np.array([-a[1], a[0], 0.0])  # a × (0, 0, −1)
    down = g * np.cos(angles) + a_x_g * np.sin(angles) + a * (a @ g) * (1.0 - np.cos(angles))
    w0 = gravity_wrench(mass, com, down[0])  # its checks of mass and com, once
    if len(down) == 1:
        return w0[None]
    f = mass * G_ACC * down / np.linalg.norm(down, axis=1, keepdims=True)
    return np.concatenate([f, cross3(np.asarray(com, float), f)], axis=1)


__all__ = ["TASKS", "task_wrenches"]
