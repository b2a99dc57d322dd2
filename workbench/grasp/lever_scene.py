"""The lever-disturbance scene of thesis §4.1.3 (Fig 4.4; 6DFC Fig 3): its seeded grasps and each
contact model's plain prediction of them.

A parallel-jaw grasp of an elliptic cylinder (grasp axis x, cylinder axis z), each jaw's contact
an elliptic-cylinder patch with the power-law pressure of Eq. 4.3 (:mod:`workbench.sources.scenes`);
disturbances from weights hung at lever arms (:func:`~.tasks.lever_disturbances`), a force-sensor
reading per grasp, and per-grasp noise standing in for physical noise (friction and the true
grasp force around the reading).  The sensitivity experiment and both engine-judged ones draw
their grasps here, so one seed gives them the same grasps.  A model's prediction of all the
grasps of one set of profiles: :func:`predict_resisted`; of one grasp with its own profiles (a
scene of many objects): :func:`predict_grasp`.

``config`` is a mapping with the sensitivity experiment's keys (its ``check_config`` judges
them): ``seed``, ``n_disturbances``, ``weight_range`` [N], ``lever_x`` and ``lever_z`` [m],
``force_range`` [N], ``mu``, ``noise_mu`` and ``noise_force`` (relative standard deviations)
for the draw; ``a``, ``b``, ``half_angle``, ``n_elements`` and ``M`` for the profiles and sets.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence

import numpy as np

from ..limit_surface import LimitSurfaceCache, SamplerSpec
from ..profile import ContactProfile
from ..sources.scenes import elliptic_cylinder_grasp
from .contacts import ContactSet
from .models import ModelParameters, contact_sets
from .resistance import CutStore, resists
from .tasks import lever_disturbances

__all__ = ["predict_grasp", "predict_resisted", "scene_inputs", "scene_profiles", "scene_sets"]


def scene_inputs(config: Mapping) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The grasps of ``config["seed"]``: disturbances ``W`` (n, 6) [N, N m] in the object frame
    (grasp axis x), sensor forces (n,) [N], and the noisy true μ (n,) and true force (n,) [N]
    of every grasp, n = ``config["n_disturbances"]``.  One generator, drawn in this order, so
    the same seed gives the same grasps in a driver and in each worker."""
    rng = np.random.default_rng(config["seed"])
    n = config["n_disturbances"]
    W = lever_disturbances(rng, n, config["weight_range"], config["lever_x"], config["lever_z"])
    forces = rng.uniform(*config["force_range"], n)  # sensor readings
    mu_true = config["mu"] * (1 + config["noise_mu"] * rng.standard_normal(n))
    f_true = forces * (1 + config["noise_force"] * rng.standard_normal(n))
    return W, forces, mu_true, f_true


def scene_profiles(config: Mapping, k: float, length: float) -> list[ContactProfile]:
    """Both jaws' profiles of the scene at unit grasp force: the power-law exponent ``k``
    (Eq. 4.3) and contact ``length`` [m] along the cylinder axis, the rest from ``config``."""
    return elliptic_cylinder_grasp(
        config["a"], config["b"], config["half_angle"], length, k, 1.0, config["n_elements"]
    )


def scene_sets(
    profiles: Sequence[ContactProfile],
    model: str,
    cache: LimitSurfaceCache,
    config: Mapping,
    sampler: str | None = None,
) -> list[ContactSet]:
    """Every contact set of ``model`` over the jaws' ``profiles``, with ``config["M"]``
    linearisation directions; limit surfaces trained by the sampler kind ``sampler``
    (:class:`~workbench.limit_surface.SamplerSpec`; None: the configured default)."""
    spec = None if sampler is None else SamplerSpec(kind=sampler)
    params = ModelParameters(M=config["M"], sampler=spec)
    return [c for p in profiles for c in contact_sets(p, model, params, cache=cache)]


def predict_resisted(
    sets: Sequence[ContactSet], W: np.ndarray, forces: np.ndarray, mu: float, cuts: CutStore
) -> tuple[np.ndarray, float]:
    """A model's plain prediction of each grasp: ``sets`` (at unit force) scaled by the grasp's
    sensor force, resisting its disturbance ``W[i]`` at friction ``mu`` (Eq. 2.100).  Returns
    (resisted (n,) bool, median milliseconds per grasp)."""
    out, times = [], []
    for w, f in zip(W, forces, strict=True):
        t0 = time.perf_counter()
        out.append(bool(resists([c.with_force(c.force * f) for c in sets], w, mu, cuts=cuts)))
        times.append(time.perf_counter() - t0)
    return np.array(out), float(np.median(times) * 1e3)


def predict_grasp(
    profiles: Sequence[ContactProfile],
    model: str,
    w: np.ndarray,
    mu: float,
    params: ModelParameters,
    cache: LimitSurfaceCache,
) -> tuple[bool, float]:
    """One grasp's plain prediction by ``model`` when each grasp has its own profiles (a
    scene of many objects, e.g. the bottle family's FEM pad profiles): the model's contact sets
    of ``profiles`` — already at the sensor's force, so not rescaled — built with ``params``
    (limit surfaces from ``cache``), resisting the disturbance ``w`` (6,) [N, N m] at friction
    ``mu`` (Eq. 2.100), with a fresh cut store.  Returns (resisted, milliseconds to build the
    sets and decide) — the build counts, unlike :func:`predict_resisted`'s, since it is per grasp.
    """
    t0 = time.perf_counter()
    sets = [c for p in profiles for c in contact_sets(p, model, params, cache=cache)]
    held = bool(resists(sets, w, mu, cuts=CutStore()))
    return held, (time.perf_counter() - t0) * 1e3
