"""Side grasps of the thesis's bottle family (§3.5.2, Fig 3.11(a)) as a grasp scene.

The Fig 4.4 / Table 4.1 scene (:mod:`.scenes`) is one elliptic-cylinder patch; the bottle family
(:mod:`workbench.fem.bottle`) gives the curved, tapered, twisted and leaning walls a parallel-jaw
gripper meets on real bottles.  A grasp here is horizontal, through the centre of the bottle's
cross-section at its height, at an angle to the section's axes, kept when both wall normals lie
inside the friction cone of the grasp axis and neither pad first meets the wall at its edge
(:func:`workbench.grasp.sampling.horizontal_grasps`).

The scene's disturbances are written in the *grasp frame* (:func:`grasp_frame`: x the grasp axis,
z the bottle's up made perpendicular to it, origin the grasp centre) — the frame of
:func:`workbench.grasp.tasks.lever_disturbances` — and moved to the bottle's own frame by
:func:`wrenches_to_object` for the models and the engine, which both work in the mesh's frame.
"""

from __future__ import annotations

import logging
from collections import Counter
from collections.abc import Mapping, Sequence
from functools import lru_cache

import numpy as np

from workbench.fem.bottle import Bottle, BottleParams, bottle_family
from workbench.quiet_log import quieted

log = logging.getLogger(__name__)

__all__ = ["bottle_grasp_pool", "bottle_mesh", "draw_pool_grasps", "grasp_frame", "wrenches_to_object"]

#: the triangle mesh of a bottle wall: (points around, rings up); ~1.5 mm edges on a 35 mm
#: bottle, finer than the pad's 1 mm-deep contact needs for the FEM pad and the engine alike
MESH_RESOLUTION = (128, 160)


@lru_cache(maxsize=32)
def bottle_mesh(params: BottleParams, resolution: tuple[int, int] = MESH_RESOLUTION):
    """Watertight mesh (``trimesh.Trimesh``, metres, base at z = 0) of ``params``'s bottle; cached
    per process (treat it as read-only)."""
    return Bottle(params).to_trimesh(*resolution)


def bottle_grasp_pool(
    n_bottles: int,
    n_asymmetric: int,
    family_seed: int,
    height_fractions,
    n_angles: int,
    mu: float,
    pad: tuple[float, float] = (0.02, 0.04),
) -> list[dict]:
    """Every kept side grasp of the first ``n_bottles`` of the bottle family
    (:func:`~workbench.fem.bottle.bottle_family` with ``n_asymmetric`` leaning, seed
    ``family_seed``) at each of ``height_fractions`` of the bottle's height × ``n_angles`` axis
    angles in [0, π) from the section's major axis, the line through the section's centre.

    ``pad`` (width, length) [m] is the jaw's pad, its length vertical.  Returns dicts with
    ``bottle`` (index in the family), ``height_fraction``, and :func:`horizontal_grasps`'s
    ``p1``, ``p2``, ``axis``, ``center``, ``width`` in the bottle's frame [m]; an empty pool
    raises ``ValueError`` (the friction cone too narrow for every wall: raise ``mu``)."""
    from workbench.grasp.sampling import horizontal_grasps
    from workbench.seeds import check_seed

    for name, value, lo in (("n_bottles", n_bottles, 1), ("n_asymmetric", n_asymmetric, 0)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
            raise ValueError(f"{name} must be an integer >= {lo}; got {value!r}")
    if n_asymmetric > n_bottles:
        raise ValueError(f"n_asymmetric ({n_asymmetric}) must be at most n_bottles ({n_bottles})")
    check_seed(family_seed, "family_seed", generator=False)
    fr = np.atleast_1d(np.asarray(height_fractions, float))
    if fr.size == 0 or fr.ndim != 1 or not ((fr > 0) & (fr < 1)).all():
        raise ValueError(
            f"height_fractions must be fractions of the bottle's height in (0, 1), e.g. [0.3, 0.5, 0.7]; "
            f"got {np.asarray(height_fractions).tolist()}"
        )
    family = bottle_family(n_bottles, n_asymmetric, family_seed)
    pool, dropped = [], Counter()
    sampler_log = logging.getLogger(horizontal_grasps.__module__)
    with quieted(sampler_log):  # one line below for the pool, not one per empty height
        for j, params in enumerate(family):
            bottle, mesh = Bottle(params), bottle_mesh(params)
            for f in fr:
                z = float(f) * params.height
                centre = bottle.section(z)[0]
                kept = horizontal_grasps(mesh, [z], n_angles, mu, centre=centre, pad=pad, progress=False)
                dropped.update(kept.dropped)
                pool += [{"bottle": j, "height_fraction": float(f), **g} for g in kept]
    if not pool:
        raise ValueError(
            f"no side grasp of the {n_bottles} bottles has both walls inside the friction cone "
            f"(mu = {mu}) with a pad clear of its edges: raise mu or add heights / angles"
        )
    log.info("bottle grasp pool: %d grasps on %d bottles; dropped %s", len(pool), n_bottles, dict(dropped))
    return pool


def draw_pool_grasps(
    pool: Sequence[Mapping], W_grasp: np.ndarray, seed: int
) -> tuple[np.ndarray, np.ndarray]:
    """Draw ``n = len(W_grasp)`` grasps from ``pool`` (:func:`bottle_grasp_pool`'s dicts) without
    repeats, with the generator of stream ``[seed, 1]`` (the second stream of the seed that drew
    the disturbances, :func:`workbench.grasp.lever_scene.scene_inputs`), and move disturbance
    ``W_grasp[i]`` (grasp frame: force [N], torque about the grasp centre [N m]) into grasp
    ``idx[i]``'s object frame (:func:`grasp_frame` of its ``axis``, :func:`wrenches_to_object`
    about its ``center``).  Returns (idx (n,) int pool indices, W_object (n, 6)).  The same seed,
    n and pool size give the same grasps; the draw does not depend on the wrenches' values."""
    from workbench.seeds import check_seed

    seed = check_seed(seed, "seed", generator=False)
    W = np.asarray(W_grasp, float)
    if W.ndim != 2 or W.shape[1] != 6 or len(W) == 0:
        raise ValueError(
            f"W_grasp must be the disturbances (n, 6), n >= 1, in the grasp frame; got shape {W.shape}"
        )
    n = len(W)
    if n > len(pool):
        raise ValueError(
            f"{n} grasps cannot be drawn without repeats from a pool of {len(pool)}: draw fewer or "
            "pool more grasps (bottles, heights or angles of bottle_grasp_pool)"
        )
    idx = np.random.default_rng([seed, 1]).choice(len(pool), n, replace=False)
    W_obj = np.vstack(
        [wrenches_to_object(W[i], grasp_frame(pool[k]["axis"]), pool[k]["center"]) for i, k in enumerate(idx)]
    )
    return idx, W_obj


def grasp_frame(axis, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """(3, 3) rotation whose rows are the grasp frame's x (``axis``), y = z × x and z (``up``
    made perpendicular to the axis) in the object frame: ``v_grasp = R @ v_object``."""
    from .jaws import check_direction

    x = check_direction(axis, "axis", "the grasp axis, jaw 1 into the object")
    u = check_direction(up, "up", "the object's up, across the grasp axis")
    z = u - (u @ x) * x
    if not np.linalg.norm(z) > 1e-9:
        raise ValueError(f"up {up!r} is parallel to the grasp axis {axis!r}: the grasp frame is undefined")
    z = z / np.linalg.norm(z)
    return np.vstack([x, np.cross(z, x), z])


def wrenches_to_object(W_grasp, R: np.ndarray, centre) -> np.ndarray:
    """Wrenches (n, 6) given in the grasp frame (force, torque about the grasp centre) as the
    same loads in the object frame about its origin: ``f_o = Rᵀ f``, ``τ_o = Rᵀ τ + c × f_o``
    (``R`` from :func:`grasp_frame`, ``centre`` c (3,) the grasp centre in the object frame)."""
    from workbench.plausible import check

    W = np.atleast_2d(np.asarray(W_grasp, float))
    R = np.asarray(R, float)
    c = np.asarray(centre, float)
    if W.ndim != 2 or W.shape[1] != 6 or not np.isfinite(W).all():
        raise ValueError(
            f"W_grasp must be finite wrenches (n, 6): force [N], torque [N m]; got shape {W.shape}"
        )
    # a rotation to round-off: orthonormal rows, right-handed (grasp_frame gives one)
    if R.shape != (3, 3) or not np.allclose(R @ R.T, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ValueError(
            f"R must be a rotation (3, 3), e.g. grasp_frame(axis); got {np.round(R, 4).tolist()}"
        )
    if c.shape != (3,) or not np.isfinite(c).all():
        raise ValueError(f"centre must be the grasp centre (3,) [m]; got {c.tolist()}")
    check(
        "lever", float(np.linalg.norm(c)), "|centre| [m] (the grasp centre's distance from the object origin)"
    )
    f = W[:, :3] @ R
    tau = W[:, 3:] @ R + np.cross(c, f)
    return np.hstack([f, tau])
