"""The linear and the geometrically nonlinear wall of a measured object at the same grasps.

A measured plastic cup closes 4–23 mm at 10 N per jaw — up to half its radius — where
small-strain linear theory (:mod:`workbench.fem.wall`) may no longer hold; the St.
Venant–Kirchhoff wall (:mod:`workbench.fem.wall_nonlinear`) holds there.  Each step as a
function of plain arguments (the wall-nonlinear experiment is their driver):

* :func:`measured_object_wall`: the object's wall geometry and linear wall, its grasps and
  measured stiffness, read from the ``deformable_objects`` folder;
* :func:`linear_at_grasps`: the linear wall at every grasp, calibrated by one factor on its
  Young's modulus (``s ∝ E`` exactly), a :class:`LinearCalibration`;
* :func:`pick_grasps`: the grasps of the nonlinear load curves, spread over the heights;
* :func:`grasp_load_curves`: at one grasp the nonlinear load curve and the linear squeeze on
  the same grasp-frame mesh;
* :func:`grasp_comparison`: both models' stiffness, closing and work at the force at one grasp;
* :func:`calibrate_models`: each model with its own single E (the nonlinear one through the
  f / E scaling of its load curves: :func:`nonlinear_scale`), and on random halves of the
  grasps scored on the rest (:func:`workbench.fem.calibration.split_scores`), a
  :class:`ModelCalibration`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .material import Material

__all__ = [
    "LinearCalibration",
    "ModelCalibration",
    "calibrate_models",
    "grasp_comparison",
    "grasp_load_curves",
    "linear_at_grasps",
    "measured_object_wall",
    "nonlinear_scale",
    "nonlinear_stiffness",
    "pick_grasps",
]

#: stiffness [N/m] at and above which a grasp counts as rigid, the measured maps' and the
#: linear wall's (the maps mark rigid with 8e10)
RIGID = 1e9
#: the largest factor on E the nonlinear calibration searches (100 x the linear model's E)
MAX_SCALE = 100.0


def measured_object_wall(
    data_dir: str | Path, name: str, material: Material, *, thickness: float, mesh: Sequence[int]
) -> tuple:
    """The measured object ``name`` of the ``deformable_objects`` folder ``data_dir``
    (``meshes/<name>.obj``, ``stiffness_maps/<name>.json``): ``(geo, wall, L, measured)`` —
    its wall geometry and linear wall of ``material``, ``thickness`` [m] and ``mesh``
    (hexes around, along the height) (:func:`workbench.fem.object_wall.object_wall`), its grasp
    locations ``L`` (2n, 3) [m] (jaw a of grasp k at row k, jaw b at k + n) and measured
    stiffness (n,) [N/m].  ``ValueError`` when the map has no measured stiffness."""
    import trimesh

    from .object_wall import object_wall
    from .wall_grasps import read_locations

    d = Path(data_dir)
    surface = trimesh.load(d / "meshes" / f"{name}.obj", force="mesh")
    smap = d / "stiffness_maps" / f"{name}.json"
    L, measured = read_locations(smap)
    if measured is None:
        raise ValueError(
            f"{name}: the map has no 'stiffness_map' to compare with — expected the measured stiffness "
            f"per grasp in {smap}, got only its 'stiffness_locations'; choose a measured object"
        )
    nt, nz = mesh
    geo, wall = object_wall(surface, material, thickness=thickness, n_theta=nt, n_z=nz)
    return geo, wall, L, measured


@dataclass(frozen=True)
class LinearCalibration:
    """The linear wall at every grasp (:func:`linear_at_grasps`), arrays read-only.

    stiffness : (n,) [N/m] at the wall's Young's modulus (NaN where the squeeze failed);
    ok : (n,) bool, the grasps both the wall and the measured map resolve (finite, below
        :data:`RIGID`);
    scale : the one factor on E that matches the measured stiffness in the median of log
        ratios over the ``ok`` grasps: ``exp(median log(measured / stiffness))``.
    """

    stiffness: np.ndarray
    ok: np.ndarray
    scale: float

    def __post_init__(self) -> None:
        for name, dtype in (("stiffness", float), ("ok", bool)):
            arr = np.array(getattr(self, name), dtype=dtype)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)


def linear_at_grasps(wall: Any, geo: Any, L: np.ndarray, measured: np.ndarray) -> LinearCalibration:
    """The linear ``wall`` built on ``geo`` (:func:`measured_object_wall`) squeezed at every grasp
    of ``L`` (2n, 3) [m] (:func:`workbench.fem.wall_grasps.stiffness_at`), calibrated on the
    ``measured`` (n,) [N/m] stiffness by one factor on E (``s ∝ E``): a :class:`LinearCalibration`."""
    from .wall_grasps import stiffness_at

    measured = np.asarray(measured, float)
    if measured.shape != (len(L) // 2,):
        raise ValueError(
            f"measured must be (n,) for the n = {len(L) // 2} grasps of L (2n, 3); got {measured.shape} — "
            "pass the map's stiffness_map with its stiffness_locations"
        )
    rows = stiffness_at(wall, geo, L)
    s = np.array([r["stiffness"] for r in rows])
    ok = np.isfinite(s) & (s < RIGID) & (measured < RIGID)
    return LinearCalibration(s, ok, float(np.exp(np.median(np.log(measured[ok] / s[ok])))))


def pick_grasps(
    ok: np.ndarray,
    z: np.ndarray,
    *,
    n_grasps: int,
    grasps: Sequence[int] | None = None,
    name: str = "the object",
) -> np.ndarray:
    """The grasps of the nonlinear load curves: ``grasps`` as given (each must be one of the
    ``ok`` (n,) bool grasps), or ``n_grasps`` of the ``ok`` ones spread over their heights ``z``
    (n,) [m], base to lip (one: the middle one by height; more than there are: every one once).
    Returns the grasp indices (k,) int; ``name`` names the object in the error."""
    ok, z = np.asarray(ok, bool), np.asarray(z, float)
    cand = np.flatnonzero(ok)
    if grasps is None:
        n_pick = min(n_grasps, cand.size)
        at = np.linspace(0, cand.size - 1, n_pick) if n_pick > 1 else [cand.size // 2]
        return cand[np.argsort(z[cand])][np.round(at).astype(int)]
    pick = np.asarray(grasps, int)
    bad = [int(k) for k in pick if not (0 <= k < ok.size and ok[k])]
    if bad:
        raise ValueError(
            f"grasps {bad} of {name} are not grasps 0..{ok.size - 1} that both the map and the linear "
            f"wall resolve (rigid or failed); choose among {cand.tolist()}"
        )
    return pick


def grasp_load_curves(
    geo: Any,
    material: Material,
    points: np.ndarray,
    *,
    n_theta: int,
    force: float,
    force_stop: float,
    step: float,
    max_closing: float,
) -> dict:
    """One grasp of ``geo`` (:class:`workbench.fem.object_wall.WallGeometry`) from jaw point
    ``points[0]`` to ``points[1]`` ((2, 3) [m]), its wall of ``material`` built in the grasp's
    frame with ``n_theta`` hexes around (:func:`workbench.fem.wall_nonlinear.grasp_frame_wall`):

    * the nonlinear wall's load curve up to the mean jaw force ``force_stop`` [N], closing by
      ``step`` [m] up to ``max_closing`` [m] (:func:`workbench.fem.wall_nonlinear.squeeze_nonlinear`);
    * the linear squeeze to ``force`` [N] on the same mesh (:func:`workbench.fem.wall.squeeze`;
      its closing decides whether a jaw reaches the clamped base too).

    Returns JSON-ready ``{"closing": (k,) [m], "jaw_forces": (k, 2) [N], "newton_iterations",
    "on_clamp", "seconds", "s_linear" [N/m], "on_clamp_linear"}``.
    """
    from .wall import squeeze
    from .wall_nonlinear import grasp_frame_wall, squeeze_nonlinear

    w, centre = grasp_frame_wall(geo, material, points[0], points[1], n_theta=n_theta)
    res = squeeze_nonlinear(w, centre, force=force_stop, step=step, max_closing=max_closing)
    lin = squeeze(w, centre, np.array([1.0, 0.0, 0.0]), force=force)
    return {
        "closing": res.closing.tolist(),
        "jaw_forces": res.jaw_forces.tolist(),
        "newton_iterations": res.newton_iterations,
        "on_clamp": res.on_clamp,
        "seconds": res.seconds,
        "s_linear": float(lin.stiffness),
        "on_clamp_linear": bool(lin.on_clamp),
    }


def grasp_comparison(
    grasp: int, curves: Mapping, *, z: float, measured: float, s_linear_all: float, force: float
) -> dict:
    """Both models at grasp ``grasp`` from its :func:`grasp_load_curves` ``curves``, at the jaw
    force ``force`` [N]: the linear stiffness (NaN where its jaw rests on the base), the
    nonlinear secant stiffness (:func:`workbench.fem.wall_nonlinear.curve_stiffness`), their
    ratio, closings [mm] and work ``∫ f dΔ`` [mJ] (``f² / 2s`` for the linear spring), the
    jaws' force imbalance and the load curve ``[closing mm, mean jaw force N]`` (rounded to 4
    decimals).  z : the grasp's height [m]; measured : its measured stiffness [N/m];
    s_linear_all : the linear wall's stiffness there calibrated on all grasps [N/m]
    (:class:`LinearCalibration` ``stiffness * scale``)."""
    from .wall_nonlinear import curve_stiffness

    fm = np.mean(curves["jaw_forces"], axis=1)
    s_nl, w_nl = curve_stiffness(curves["closing"], curves["jaw_forces"], force)
    s_l = np.nan if curves["on_clamp_linear"] else curves["s_linear"]
    return {
        "grasp": int(grasp),
        "z_m": float(z),
        "measured": float(measured),
        "linear_residual_log": float(np.log(measured / s_linear_all)),
        "s_linear": float(s_l),
        "s_nonlinear": s_nl,
        "rests_on_base": {"linear": curves["on_clamp_linear"], "nonlinear": bool(curves["on_clamp"])},
        "ratio_nl_lin": s_nl / s_l,
        "closing_linear_mm": force / s_l * 1e3,
        "closing_nonlinear_mm": force / s_nl * 1e3,
        "work_linear_mJ": 0.5 * force**2 / s_l * 1e3,
        "work_nonlinear_mJ": w_nl * 1e3,
        # 1e-12 N: a curve that never left zero force has no imbalance to speak of
        "jaw_force_imbalance": float(
            np.abs(np.diff(np.asarray(curves["jaw_forces"])[-1]))[0] / max(fm[-1], 1e-12)
        ),
        "load_curve_mm_N": np.column_stack([np.asarray(curves["closing"]) * 1e3, fm]).round(4).tolist(),
        "newton_iterations": curves["newton_iterations"],
        "seconds": curves["seconds"],
    }


def nonlinear_stiffness(curves: Sequence[Mapping], force: float, e_scale: float = 1.0) -> np.ndarray:
    """(n,) secant stiffness [N/m] at ``force`` [N] of the walls of the load ``curves`` (each
    ``closing`` (k,) [m], ``jaw_forces`` (k, 2) [N]) with Young's modulus × ``e_scale``
    (:func:`workbench.fem.wall_nonlinear.curve_stiffness`; NaN where a curve stops below it)."""
    from .wall_nonlinear import curve_stiffness

    return np.array([curve_stiffness(cv["closing"], cv["jaw_forces"], force, e_scale)[0] for cv in curves])


def nonlinear_scale(
    curves: Sequence[Mapping], measured: np.ndarray, *, force: float, force_stop: float
) -> float:
    """The factor ``c`` on the curves' Young's modulus at which the median of
    ``log(s_nonlinear(c) / measured)`` over the grasps is zero (Brent's method): the nonlinear
    wall's one-scalar calibration, through the f / E scaling of its load ``curves`` (n,)
    (:func:`nonlinear_stiffness`).  measured : (n,) [N/m]; force : the jaw force of the
    stiffness [N]; force_stop : the force the curves were run to [N], which bounds ``c`` from
    below (``force / force_stop``, 1e-4 above: the curve's last point); ``c`` at most
    :data:`MAX_SCALE`.  NaN when no ``c`` in that range brackets the zero."""
    from scipy.optimize import brentq

    measured = np.asarray(measured, float)

    def misfit(c: float) -> float:  # a curve stopping below force at E x c: too soft everywhere
        s = nonlinear_stiffness(curves, force, c)
        return float(np.median(np.log(s / measured))) if np.isfinite(s).all() else -np.inf

    lo = force / force_stop * 1.0001
    return brentq(misfit, lo, MAX_SCALE) if misfit(lo) < 0 < misfit(MAX_SCALE) else float("nan")


@dataclass(frozen=True)
class ModelCalibration:
    """The answer of :func:`calibrate_models`.

    scale_linear, scale_nonlinear : each model's own factor on ``E_lin`` (NaN: the nonlinear
        one found none);
    compare : ``{"linear", "nonlinear"}`` → None (no factor) or ``{"E_effective_Pa",
        "median_abs_log_ratio", "spearman"}`` on all the grasps (Spearman None below 3 grasps);
    held_out : None below 6 grasps, else ``{"n_grasps", "linear", "nonlinear"}``, each model's
        :func:`workbench.fem.calibration.split_scores` over random halves (the nonlinear one
        None without a factor).
    """

    scale_linear: float
    scale_nonlinear: float
    compare: dict
    held_out: dict | None


def calibrate_models(
    measured: np.ndarray,
    s_linear: np.ndarray,
    curves: Sequence[Mapping],
    *,
    E_lin: float,
    force: float,
    force_stop: float,
) -> ModelCalibration:
    """Each model calibrated by its own single Young's modulus on the same n grasps, and the same
    fitted on random halves of them, scored on the rest.

    measured : (n,) measured stiffness [N/m]; s_linear : (n,) the linear wall's at ``E_lin``
    [Pa] (factor ``exp(median log(measured / s_linear))``, exact: ``s ∝ E``); curves : n load
    curves of the nonlinear wall at ``E_lin`` (:func:`grasp_load_curves`; factor
    :func:`nonlinear_scale`); force : the jaw force of the stiffness [N]; force_stop : the
    force the curves run to [N].  Returns a :class:`ModelCalibration`.
    """
    from .calibration import split_scores, split_scores_of, stiffness_scores

    meas, s_l = np.asarray(measured, float), np.asarray(s_linear, float)
    if not (meas.ndim == 1 and meas.shape == s_l.shape == (len(curves),) and meas.size):
        raise ValueError(
            "measured, s_linear and curves must hold one entry per grasp, at least one; got "
            f"{meas.shape}, {s_l.shape} and {len(curves)} curves"
        )
    c_nl = nonlinear_scale(curves, meas, force=force, force_stop=force_stop)
    c_l = float(np.exp(np.median(np.log(meas / s_l))))
    compare = {}
    for model, s in (
        ("linear", s_l * c_l),
        ("nonlinear", nonlinear_stiffness(curves, force, c_nl) if np.isfinite(c_nl) else None),
    ):
        if s is None:
            compare[model] = None
            continue
        scores = stiffness_scores(s, meas)
        compare[model] = {
            "E_effective_Pa": E_lin * (c_l if model == "linear" else c_nl),
            "median_abs_log_ratio": scores["median_abs_log_ratio"],
            "spearman": scores["spearman"] if len(meas) > 2 else None,
        }
    if len(meas) < 6:  # halves of fewer than three grasps score nothing
        return ModelCalibration(c_l, c_nl, compare, None)

    def nl_predict(train: np.ndarray) -> np.ndarray:
        c = nonlinear_scale([curves[i] for i in train], meas[train], force=force, force_stop=force_stop)
        return nonlinear_stiffness(curves, force, c) if np.isfinite(c) else np.full(len(meas), np.nan)

    held = {"n_grasps": len(meas), "linear": split_scores(s_l, meas)}
    held["nonlinear"] = split_scores_of(nl_predict, meas) if np.isfinite(c_nl) else None
    return ModelCalibration(c_l, c_nl, compare, held)
