"""Offscreen figures: pyvista renders of contact profiles with friction arrows
(Fig 3.3 style).  Nothing here needs a display."""

from __future__ import annotations

import io
import numbers
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..profile import ContactProfile
from ..wrench import check_twists, friction_directions
from .results import save_png


def _pyvista():
    import pyvista as pv
    import vtk

    pv.OFF_SCREEN = True
    # VTK logs an X-server warning before falling back to offscreen rendering
    vtk.vtkLogger.SetStderrVerbosity(vtk.vtkLogger.VERBOSITY_ERROR)
    return pv


def save_screenshot(plotter: Any, path: Path) -> Path:
    """Render an offscreen plotter to ``path`` (PNG, atomic) and close it."""
    from PIL import Image

    img = plotter.screenshot(return_img=True)
    plotter.close()
    buf = io.BytesIO()
    Image.fromarray(img).save(buf, format="PNG")
    return save_png(path, buf.getvalue())


def profile_polydata(profile: ContactProfile) -> Any:
    """``pyvista.PolyData`` of a meshed profile with ``pressure`` cell data."""
    pv = _pyvista()
    if profile.vertices is None or profile.faces is None:
        raise ValueError("profile has no mesh (vertices/faces) to render; build it with from_mesh")
    k = profile.faces.shape[1]
    cells = np.hstack([np.full((len(profile.faces), 1), k), profile.faces]).ravel()
    poly = pv.PolyData(profile.vertices, cells)
    poly.cell_data["pressure"] = profile.pressures
    return poly


def _check_twist_panels(twists: Any) -> None:
    """ValueError unless ``twists`` is a non-empty ``{label: (6,) finite twist}`` mapping."""
    if not isinstance(twists, Mapping):
        shape = f" of shape {np.shape(twists)}" if isinstance(twists, np.ndarray) else ""
        raise ValueError(
            f"twists must be a dict {{label: (6,) twist [v; ω]}}, one panel each; got "
            f"{type(twists).__name__}{shape} — for the rows of a (K, 6) array pass "
            "{f'twist {i}': xi for i, xi in enumerate(array)}"
        )
    if not twists:
        raise ValueError("twists is empty: give at least one {label: (6,) twist} to draw a panel")
    for label, xi in twists.items():
        try:  # the one rule of a twist array (numeric, finite, 6 components)
            arr, single = check_twists(xi)
        except ValueError as exc:
            raise ValueError(f"twists[{label!r}]: {exc}") from None
        if not single:
            raise ValueError(
                f"twists[{label!r}] must be one (6,) twist [v_x, v_y, v_z, ω_x, ω_y, ω_z]; got shape "
                f"{arr.shape} — one panel per twist: split a (K, 6) array into K entries"
            )


def render_friction_arrows(
    profile: ContactProfile,
    twists: dict[str, np.ndarray],
    path: Path,
    *,
    title: str = "",
    max_arrows: int = 400,
    window_size: tuple[int, int] = (520, 460),
) -> Path:
    """One panel per twist: the surface and the local friction-force
    directions on the object (green), like thesis Fig 3.3.

    profile : a meshed ContactProfile (``from_mesh``).  twists : ``{label: (6,) twist}``, one
    panel each, in order (labels as panel titles).  ValueError for anything else, before
    anything is rendered.
    """
    _check_twist_panels(twists)
    if not isinstance(profile, ContactProfile):
        raise ValueError(
            f"profile must be a ContactProfile; got {type(profile).__name__} — build one with "
            "ContactProfile.from_mesh(vertices, faces, pressures)"
        )
    if isinstance(max_arrows, bool) or not isinstance(max_arrows, numbers.Integral) or max_arrows < 1:
        raise ValueError(f"max_arrows must be an integer >= 1 (arrows per panel); got {max_arrows!r}")
    pv = _pyvista()
    poly = profile_polydata(profile)
    n_panels = len(twists)
    plotter = pv.Plotter(
        off_screen=True, shape=(1, n_panels), window_size=(window_size[0] * n_panels, window_size[1])
    )
    stride = max(1, len(profile) // max_arrows)
    idx = np.arange(0, len(profile), stride)
    length = 0.05 * profile.length_scale
    # a uniform pressure (equal to round-off) gets one colour, not a noise colour map
    uniform = np.ptp(profile.pressures) <= 1e-12 * profile.pressures.max()
    for j, (label, xi) in enumerate(twists.items()):
        plotter.subplot(0, j)
        if uniform:
            plotter.add_mesh(poly, color="lightsteelblue", show_edges=True, edge_color="gray", opacity=0.9)
        else:
            bar = {"title": "pressure [Pa]", "fmt": "%.2g", "n_labels": 3}
            plotter.add_mesh(poly, scalars="pressure", show_edges=False, cmap="viridis", scalar_bar_args=bar)
        d = friction_directions(profile, xi)[idx]
        pts = pv.PolyData(profile.centers[idx] + 0.05 * length * profile.normals[idx])  # just off the surface
        pts["d"] = d
        arrows = pts.glyph(orient="d", scale=False, factor=length)
        plotter.add_mesh(arrows, color="forestgreen")
        plotter.add_text(f"{title} {label}".strip(), font_size=10)
        plotter.add_axes()
        # look from the side the normals point to (the jaw side), tilted for depth
        mean_n = profile.normals.mean(axis=0)
        if np.linalg.norm(mean_n) > 0.5 and abs(mean_n[2]) > 0.9:
            plotter.view_vector(mean_n + np.array([0.4, -0.6, 0.0]))
        else:
            plotter.camera_position = "iso"
            plotter.camera.azimuth = 30
    return save_screenshot(plotter, path)
