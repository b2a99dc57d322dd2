"""Offscreen figures of a stiffness validation: measured stiffness of an
object's antipodal grasps against a calibrated model's prediction (thesis §4.3.3.1,
Fig. 4.13).

* :func:`plot_stiffness_validation` — log–log scatter, one panel per object: held-out
  grasps filled, training grasps hollow, the line ``y = x`` and the acceptance band
  ``|log(s_pred / s_meas)| <= band``; the title gives the held-out Spearman and median
  ``|log ratio|`` and how many grasps were left out (rigid or failed);
* :func:`render_stiffness_maps` — the object mesh twice (measured | predicted), its
  surface coloured by the interpolated map of each side's values
  (:class:`~workbench.grasp.stiffness_map.StiffnessMap` on the mesh vertices), the
  grasp locations as spheres, one logarithmic colour scale [N/m], rigid in grey;
  front and back views.

Pure functions of arrays; matplotlib with the Agg backend and pyvista offscreen, so
nothing needs a display.  Stiffness is in N/m, lengths in metres.
"""

from __future__ import annotations

import logging
import numbers
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from .. import config
from ..stats import rank_correlation

log = logging.getLogger(__name__)

__all__ = ["MapStyle", "plot_stiffness_validation", "render_stiffness_maps"]

#: acceptance band of the validation: median |log(s_pred / s_meas)| of the held-out grasps
LOG_BAND = 0.35
RIGID_COLOR = "lightgrey"
CMAP = "viridis"


def _threshold(rigid_threshold: float | None) -> float:
    return config.TOL.rigid_stiffness_threshold if rigid_threshold is None else float(rigid_threshold)


def _positive(x) -> bool:
    return (
        isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_)) and bool(np.isfinite(x) and x > 0)
    )


def _check_options(path, band, rigid_threshold, model) -> None:
    """The figure options of :func:`plot_stiffness_validation`, before anything is drawn."""
    if not isinstance(path, (str, os.PathLike)):
        raise ValueError(
            f"path must be the output PNG, a str or Path; got {type(path).__name__} {path!r:.60}"
        )
    if not _positive(band):
        raise ValueError(
            f"band must be a finite width > 0 in |log(predicted / measured)| (natural log), e.g. {LOG_BAND}; "
            f"got {band!r}"
        )
    _check_rigid_threshold(rigid_threshold)
    _check_model_name(model)


def _check_rigid_threshold(rigid_threshold) -> None:
    if rigid_threshold is not None and not _positive(rigid_threshold):
        raise ValueError(
            f"rigid_threshold must be a stiffness > 0 [N/m] (None: config.TOL.rigid_stiffness_threshold); "
            f"got {rigid_threshold!r}"
        )


def _check_model_name(model) -> None:
    if not isinstance(model, str):
        raise ValueError(f"model must be a str naming the prediction (the y label); got {model!r}")


def _check_grasps(
    measured,
    predicted,
    train,
    test,
    *,
    where: str,
    rigid_threshold: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Validated (n,) float measured, (n,) float predicted, (n,) bool train, (n,) bool test."""
    s = _numbers(measured, f"{where}: measured")
    p = _numbers(predicted, f"{where}: predicted")
    if s.ndim != 1 or len(s) == 0:
        raise ValueError(
            f"{where}: measured must be (n,) stiffness [N/m], one per grasp; got shape {s.shape}"
        )
    n = len(s)
    if p.shape != (n,):
        raise ValueError(
            f"{where}: predicted must be (n,) = ({n},) like measured, one per grasp [N/m] (NaN for a failed "
            f"model); got shape {p.shape}"
        )
    _check_values(s, p, where)
    masks = []
    for label, m in (("train", train), ("test", test)):
        m = np.zeros(n, dtype=bool) if m is None else np.asarray(m)
        if m.shape != (n,) or m.dtype != bool:
            raise ValueError(
                f"{where}: {label} must be an (n,) = ({n},) boolean mask over the grasps; got shape "
                f"{m.shape}, dtype {m.dtype} (index arrays: build a mask with np.isin(np.arange(n), idx))"
            )
        masks.append(m)
    tr, te = masks
    if (tr & te).any():
        k = int(np.argmax(tr & te))
        raise ValueError(f"{where}: grasp {k} is in both train and test; the halves must be disjoint")
    used = tr | te
    good = np.isfinite(s) & np.isfinite(p) & (s > 0) & (p > 0) & (s < rigid_threshold) & (p < rigid_threshold)
    if (used & ~good).any():
        k = int(np.argmax(used & ~good))
        raise ValueError(
            f"{where}: grasp {k} is in train/test but measured {s[k]:g} / predicted {p[k]:g} N/m is not "
            f"a finite non-rigid stiffness (< {rigid_threshold:g}); leave rigid and failed grasps out of "
            "both masks"
        )
    return s, p, tr, te


def _numbers(values, what: str) -> np.ndarray:
    """``values`` as a float array, or a ``ValueError`` naming ``what`` (not numpy's)."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(
            f"{what} must be an array of stiffness values [N/m], one per grasp; got {type(values).__name__} "
            f"{values!r:.60}"
        ) from None


def _check_values(s: np.ndarray, p: np.ndarray, where: str) -> None:
    """Measured ``s`` (n,) and predicted ``p`` (n,) stiffness [N/m] by the one stiffness rule
    (:func:`~workbench.grasp.stiffness_map.check_stiffness`: > 0, inf for rigid, the softest and
    stiffest finite value plausible — 5 is "probably in N/mm"); a NaN prediction is a failed model
    and is not judged."""
    from ..grasp.stiffness_map import check_stiffness

    fix = "one value per grasp, in the order of the grasps"
    for label, v in (("measured", s), ("predicted", np.where(np.isnan(p), np.inf, p))):
        try:
            check_stiffness(v, len(v), "grasp", fix=fix)
        except ValueError as exc:
            raise ValueError(f"{where}: {label} {exc}") from None


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _heldout_stats(s: np.ndarray, p: np.ndarray, test: np.ndarray) -> tuple[float, float]:
    """Spearman and median |log(p / s)| of the held-out grasps (NaN if fewer than 2 / none)."""

    rho = rank_correlation(p[test], s[test]) if test.sum() >= 2 else float("nan")
    mal = float(np.median(np.abs(np.log(p[test] / s[test])))) if test.any() else float("nan")
    return rho, mal


def plot_stiffness_validation(
    panels: Mapping[str, Mapping[str, np.ndarray]],
    path: Path,
    *,
    band: float = LOG_BAND,
    rigid_threshold: float | None = None,
    model: str = "FEM, calibrated",
) -> Path:
    """Measured against predicted stiffness, log–log, one panel per object; saved as PNG.

    panels : object name -> mapping with
        ``measured`` (n,) float — measured stiffness per grasp [N/m]; ``>= rigid_threshold``
        (or inf) marks a rigid grasp;
        ``predicted`` (n,) float — the calibrated model's stiffness [N/m] (NaN: failed);
        ``train`` (n,) bool — grasps the calibration used (drawn hollow);
        ``test`` (n,) bool — held-out grasps (filled; the title's statistics);
        grasps in neither mask (rigid, failed) are left out and counted in the title.
    path : output PNG, written atomically.
    band : the acceptance band in ``|log(predicted / measured)|`` (natural log), drawn
        around ``y = x``.
    rigid_threshold : [N/m]; None: ``config.TOL.rigid_stiffness_threshold``.
    model : what ``predicted`` is, for the y label.

    Returns ``path``.  Raises ``ValueError``, before anything is drawn, when ``panels`` is not
    a dict of dicts, an option has the wrong type, an object's arrays disagree in length, a
    stiffness is not one by :func:`~workbench.grasp.stiffness_map.check_stiffness` (<= 0, or the
    softest below ``config.TOL.min_plausible_stiffness``: N/mm given as N/m), a mask is not
    boolean, the masks overlap, or a masked grasp is rigid or non-finite.
    """
    from .results import save_figure

    if not isinstance(panels, Mapping) or not panels:
        raise ValueError(
            "panels must be a dict naming at least one object: {name: {'measured': (n,), 'predicted': (n,), "
            f"'train': (n,) bool, 'test': (n,) bool}}; got {type(panels).__name__} {panels!r:.60} — for one "
            "object pass {'object': {...}}"
        )
    _check_options(path, band, rigid_threshold, model)
    thr = _threshold(rigid_threshold)
    data = {name: _check_panel(name, d, thr) for name, d in panels.items()}
    plt = _pyplot()
    k = len(data)
    fig, axes = plt.subplots(1, k, figsize=(4.4 * k, 4.6), squeeze=False)
    for ax, (name, grasps) in zip(axes[0], data.items(), strict=True):
        _draw_panel(ax, name, grasps, thr, band, model)
    fig.tight_layout()
    return save_figure(fig, Path(path))


def _check_panel(name: str, d, thr: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One object's panel of :func:`plot_stiffness_validation`, checked: ``(s, p, train, test)``
    (:func:`_check_grasps`)."""
    if not isinstance(d, Mapping):
        raise ValueError(
            f"panels[{name!r}] must be a dict with measured, predicted, train, test; got "
            f"{type(d).__name__} {d!r:.60}"
        )
    missing = {"measured", "predicted", "train", "test"} - set(d)
    if missing:
        raise ValueError(f"{name}: panel needs measured, predicted, train, test; missing {sorted(missing)}")
    return _check_grasps(
        d["measured"], d["predicted"], d["train"], d["test"], where=name, rigid_threshold=thr
    )


def _draw_panel(ax, name: str, grasps: tuple, thr: float, band: float, model: str) -> None:
    """One object's log–log scatter on ``ax``: ``grasps`` = (measured (n,), predicted (n,),
    train (n,) bool, test (n,) bool), the line y = x, the ``band`` and the title's statistics."""
    from matplotlib.ticker import NullFormatter

    s, p, tr, te = grasps
    used = tr | te
    out = ~used
    n_rigid_meas = int(np.sum(out & (s >= thr)))
    n_rigid_model = int(np.sum(out & (s < thr) & ~(np.isfinite(p) & (p < thr))))
    rho, mal = _heldout_stats(s, p, te)
    if used.any():
        v = np.r_[s[used], p[used]]
        lo, hi = np.log10(v.min()) - 0.15, np.log10(v.max()) + 0.15
    else:
        lo, hi = 2.0, 4.0
    x = np.logspace(lo, hi, 50)
    ax.fill_between(x, x * np.exp(-band), x * np.exp(band), color="tab:green", alpha=0.12, lw=0)
    ax.plot(x, x, color="k", lw=1, label="y = x")
    ax.plot(x, x * np.exp(band), color="tab:green", lw=0.8, ls="--", label=f"±{band:g} in log")
    ax.plot(x, x * np.exp(-band), color="tab:green", lw=0.8, ls="--")
    ax.scatter(s[te], p[te], s=28, color="tab:blue", edgecolor="k", lw=0.5, label=f"held out ({te.sum()})")
    ax.scatter(
        s[tr],
        p[tr],
        s=28,
        facecolor="none",
        edgecolor="tab:orange",
        lw=1.2,
        label=f"training ({tr.sum()})",
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_minor_formatter(NullFormatter())
    ax.set_xlim(10**lo, 10**hi)
    ax.set_ylim(10**lo, 10**hi)
    ax.set_aspect("equal")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.set_xlabel("measured stiffness [N/m]")
    ax.set_ylabel(f"{model} [N/m]")
    verdict = "within" if mal <= band else "outside"
    ax.set_title(
        f"{name}\nheld out: Spearman {rho:.2f}, median |log ratio| {mal:.2f} ({verdict} {band:g})\n"
        f"left out: {n_rigid_meas} rigid measured, {n_rigid_model} rigid/failed {model.split(',')[0]}",
        fontsize=9,
    )
    ax.legend(loc="upper left", fontsize=7)
    log.info("%s: held-out Spearman %.3f, median |log ratio| %.3f", name, rho, mal)


def _surface_values(
    vertices: np.ndarray, locations: np.ndarray, values: np.ndarray, thr: float
) -> np.ndarray:
    """(V,) interpolated stiffness at the vertices from per-grasp ``values`` (n,) at
    ``locations`` (2n, 3) — NaN where rigid (grasps with non-finite values are dropped);
    all NaN if no grasp is usable."""
    from ..grasp.stiffness_map import StiffnessMap

    n = len(values)
    v = np.where(np.isfinite(values) & (values >= thr), np.inf, values)
    keep = (np.isfinite(v) & (v > 0)) | np.isinf(v)
    if not keep.any():
        return np.full(len(vertices), np.nan)
    idx = np.flatnonzero(keep)
    smap = StiffnessMap(
        locations[np.r_[idx, idx + n]], np.r_[v[idx], v[idx]], grasp=np.r_[idx, idx], rigid_threshold=thr
    )
    out = smap(vertices)
    return np.where(np.isfinite(out), out, np.nan)


@dataclass(frozen=True)
class MapStyle:
    """How :func:`render_stiffness_maps` draws: with ``surface`` the mesh coloured by the
    interpolated map (else only the grasps' spheres), ``rigid_threshold`` [N/m] from which a
    stiffness is drawn rigid (grey; None: ``config.TOL.rigid_stiffness_threshold``, read at
    drawing time), the predicted row's label ``model``, and each view's ``window_size``
    (width, height) [pixels].  ``rigid_threshold`` and ``model`` are checked as
    :func:`plot_stiffness_validation` checks them."""

    surface: bool = True
    rigid_threshold: float | None = None
    model: str = "FEM, calibrated"
    window_size: tuple[int, int] = (420, 460)

    def __post_init__(self) -> None:
        _check_rigid_threshold(self.rigid_threshold)
        _check_model_name(self.model)


def render_stiffness_maps(
    vertices,
    faces,
    locations,
    measured,
    predicted,
    path: Path,
    *,
    title: str = "",
    style: MapStyle | None = None,
) -> Path:
    """The measured and the predicted stiffness on the object's mesh; saved as PNG.

    A 2 × 2 grid: rows measured | ``style.model``; columns the object seen from −y (front)
    and from +y (back), z up.  Each grasp's two jaw points are spheres coloured by the
    stiffness; with ``style.surface`` the mesh is coloured by the interpolated map of the
    same values (:class:`~workbench.grasp.stiffness_map.StiffnessMap` at the
    vertices — rigid where the nearest grasp is rigid).  One logarithmic colour scale
    [N/m] over both rows; rigid (and failed) in grey.

    vertices : (V, 3) float — mesh vertices [m], object frame.
    faces : (F, 3) int — triangles.
    locations : (2n, 3) float — grasp contact points [m]; ``i`` and ``i + n`` are grasp
        ``i``'s two jaws (``deformable_objects/stiffness_maps/*.json`` order).
    measured : (n,) float — measured stiffness per grasp [N/m]; ``>= rigid_threshold``
        or inf is rigid.
    predicted : (n,) float — the model's stiffness per grasp [N/m]; NaN: failed.
    path : output PNG, written atomically.
    style : what to draw and how (:class:`MapStyle`); None: ``MapStyle()``.

    Returns ``path``.  Raises ``ValueError`` on arrays of the wrong shape or lengths
    that disagree (``locations`` must hold twice as many points as ``measured``).
    """
    from .viz import _pyvista, save_screenshot

    st = MapStyle() if style is None else style
    surface, window_size = st.surface, st.window_size
    V, Fc, L, s, p = _check_map_inputs(vertices, faces, locations, measured, predicted, title)
    thr = _threshold(st.rigid_threshold)
    point_vals, surf_vals, clim = _map_values(V, L, s, p, thr, st.model, surface)
    pv = _pyvista()
    extent = float(np.ptp(V, axis=0).max())
    scene = _MapScene(
        pv=pv,
        vertices=V,
        cells=np.hstack([np.full((len(Fc), 1), 3), Fc]).ravel(),
        locations=L,
        sphere=pv.Sphere(radius=0.022 * extent, theta_resolution=12, phi_resolution=12),
        center=V.mean(axis=0),
        extent=extent,
        clim=clim,
        title=title,
        n=len(s),
    )
    plotter = pv.Plotter(off_screen=True, shape=(2, 2), window_size=(2 * window_size[0], 2 * window_size[1]))
    for i, label in enumerate(point_vals):
        for j in range(len(_VIEWS)):
            plotter.subplot(i, j)
            surf = surf_vals[label] if surface else None
            _draw_view(plotter, scene, label, point_vals[label], surf, j)
    log.info("stiffness maps %s: colour scale %.3g..%.3g N/m", title or path, *clim)
    return save_screenshot(plotter, Path(path))


#: the colour bar of each row of :func:`render_stiffness_maps` (pyvista's add_scalar_bar)
_BAR = {
    "interactive": False,
    "fmt": "%.3g",
    "n_labels": 4,
    "vertical": False,
    "position_x": 0.15,
    "position_y": 0.03,
    "height": 0.07,
    "width": 0.7,
    "title_font_size": 13,
    "label_font_size": 11,
}

#: the columns of :func:`render_stiffness_maps`: (name, side of the camera along y)
_VIEWS = (("front (-y)", -1.0), ("back (+y)", 1.0))


class _MapScene(NamedTuple):
    """What every view of :func:`render_stiffness_maps` draws: the pyvista module, the mesh
    (vertices (V, 3) [m], pyvista cells), the grasp locations (2n, 3) [m] and their sphere
    glyph, the object's centre (3,) and extent [m], the colour limits [N/m], the title and the
    number of grasps."""

    pv: Any
    vertices: np.ndarray
    cells: np.ndarray
    locations: np.ndarray
    sphere: Any
    center: np.ndarray
    extent: float
    clim: tuple[float, float]
    title: str
    n: int


def _check_map_inputs(vertices, faces, locations, measured, predicted, title: str) -> tuple:
    """``(V (V, 3), faces (F, 3), locations (2n, 3), measured (n,), predicted (n,))`` of
    :func:`render_stiffness_maps`, checked (its docstring)."""
    V = np.asarray(vertices, dtype=float)
    Fc = np.asarray(faces)
    L = np.asarray(locations, dtype=float)
    if V.ndim != 2 or V.shape[1] != 3 or len(V) < 3:
        raise ValueError(f"vertices must be (V, 3) [m] with V >= 3; got shape {V.shape}")
    if Fc.ndim != 2 or Fc.shape[1] != 3 or Fc.dtype.kind not in "iu" or len(Fc) == 0:
        raise ValueError(
            f"faces must be (F, 3) integer triangles; got shape {Fc.shape}, dtype {Fc.dtype} "
            "(triangulate quads)"
        )
    if Fc.min() < 0 or Fc.max() >= len(V):
        raise ValueError(f"faces index vertices 0..{len(V) - 1}; got indices {Fc.min()}..{Fc.max()}")
    s = _numbers(measured, "measured")
    if s.ndim != 1 or len(s) == 0:
        raise ValueError(f"measured must be (n,) stiffness [N/m], one per grasp; got shape {s.shape}")
    n = len(s)
    if L.shape != (2 * n, 3):
        raise ValueError(
            f"locations must be (2n, 3) = ({2 * n}, 3) for n = {n} measured grasps (points i and i + n are "
            f"one grasp's jaws); got shape {L.shape}"
        )
    p = _numbers(predicted, "predicted")
    if p.shape != (n,):
        raise ValueError(f"predicted must be (n,) = ({n},) like measured [N/m]; got shape {p.shape}")
    _check_values(s, p, title or "render_stiffness_maps")
    if np.any(~np.isfinite(V)) or np.any(~np.isfinite(L)):
        raise ValueError("vertices and locations must be finite")
    return V, Fc, L, s, p


def _map_values(V, L, s, p, thr: float, model: str, surface: bool) -> tuple[dict, dict, tuple[float, float]]:
    """``(point values, surface values, colour limits)``: per row (measured, ``model``) the
    soft stiffness [N/m] of each grasp (n,) and, with ``surface``, at each vertex (V,) (NaN:
    rigid or failed); one colour scale over both."""

    def soft(x: np.ndarray) -> np.ndarray:
        return np.where(np.isfinite(x) & (x > 0) & (x < thr), x, np.nan)

    point_vals = {"measured": soft(s), model: soft(p)}
    surf_vals = {}
    if surface:
        surf_vals = {
            "measured": soft(_surface_values(V, L, s, thr)),
            model: soft(_surface_values(V, L, p, thr)),
        }
    finite = np.concatenate([v[np.isfinite(v)] for v in (*point_vals.values(), *surf_vals.values())])
    clim = (float(finite.min()), float(finite.max())) if finite.size else (1.0, 10.0)
    if clim[1] <= clim[0] * 1.0001:
        clim = (clim[0] / 1.5, clim[1] * 1.5)
    return point_vals, surf_vals, clim


def _draw_view(plotter, scene: _MapScene, label: str, points: np.ndarray, surf, j: int) -> None:
    """The current subplot, row ``label``, column ``j`` (:data:`_VIEWS`): the mesh (coloured by
    ``surf`` (V,) unless None), the grasps' spheres coloured by ``points`` (n,), the colour bar
    (right column), the text and the camera."""
    view, sign = _VIEWS[j]
    pv = scene.pv
    mesh = pv.PolyData(scene.vertices, scene.cells)
    common = {"cmap": CMAP, "clim": scene.clim, "log_scale": True, "nan_color": RIGID_COLOR}
    if surf is not None:
        mesh.point_data["s"] = surf
        plotter.add_mesh(
            mesh,
            scalars="s",
            smooth_shading=True,
            show_scalar_bar=False,
            **common,
        )
    else:
        plotter.add_mesh(mesh, color="whitesmoke", smooth_shading=True)
    pts = pv.PolyData(scene.locations)
    pts.point_data["s"] = np.r_[points, points]
    glyphs = pts.glyph(geom=scene.sphere, scale=False, orient=False)
    plotter.add_mesh(
        glyphs,
        scalars="s",
        show_scalar_bar=False,
        **common,
    )
    if j == 1:  # one bar per row, on the right; the trailing newline lifts the title off the labels
        plotter.add_scalar_bar(title=f"{label} [N/m]\n", **_BAR)
    n_rigid = int(np.sum(np.isnan(points)))
    text = f"{label}, {view}"
    if j == 0:
        text = f"{scene.title}\n{text}" if scene.title else text
        text += f"\ngrey: rigid/failed ({n_rigid} of {scene.n} grasps)"
    plotter.add_text(text, font_size=8, position="upper_left")
    # the focal point below the centre lifts the object above the colour bar
    look_at = scene.center - np.array([0.0, 0.0, 0.08 * scene.extent])
    plotter.camera.focal_point = look_at
    plotter.camera.position = look_at + np.array([0.0, sign * 3.2 * scene.extent, 0.8 * scene.extent])
    plotter.camera.up = (0.0, 0.0, 1.0)
    plotter.camera.zoom(1.1)
    plotter.reset_camera_clipping_range()
