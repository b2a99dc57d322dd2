"""Offscreen pyvista renders of grasps on a mesh: each model's best top grasp with its two pads
and their contacts coloured by pressure (thesis Fig 4.9(e)–(h))."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .viz import _pyvista, save_screenshot


def best_grasps_figure(mesh, best: Mapping[str, tuple], path: Path, *, title: str = "") -> Path:
    """One panel per model of ``best`` = ``{model: (contact, q)}``, each ``contact`` a
    :class:`~workbench.grasp.settle.SettledContact` on ``mesh`` (metres): the mesh in grey, both
    pads' outlines in black, the contact elements coloured by pressure [kPa], ``q`` in the title.
    Written to ``path`` (PNG, atomic)."""
    if not best:
        raise ValueError("best must map at least one model name to (contact, q)")
    pv = _pyvista()
    faces = np.hstack([np.full((len(mesh.faces), 1), 3), np.asarray(mesh.faces)]).ravel()
    surface = pv.PolyData(np.asarray(mesh.vertices, float) * 1e3, faces)
    size = float(np.max(mesh.extents)) * 1e3
    top = max(
        (float(p.pressures.max()) for c, _ in best.values() if c.touches for p in c.profiles), default=1.0
    )
    n = len(best)
    plotter = pv.Plotter(off_screen=True, shape=(1, n), window_size=(360 * n, 380), border=False)
    for i, (model, (contact, q)) in enumerate(best.items()):
        plotter.subplot(0, i)
        plotter.add_mesh(surface, color="lightgrey", opacity=0.35)
        for k, jaw in enumerate(contact.jaws):
            # the pad drawn where it touches: moved along its closing to its deepest element
            travel = 0.0
            if contact.touches:
                travel = float(np.max((contact.profiles[k].centers - jaw.origin) @ jaw.closing))
            loop = np.vstack([jaw.outline_points, jaw.outline_points[:1]]) + travel * jaw.closing
            plotter.add_mesh(pv.lines_from_points(loop * 1e3), color="black", line_width=3)
        if contact.touches:
            pts = np.vstack([p.centers for p in contact.profiles]) * 1e3
            kpa = np.concatenate([p.pressures for p in contact.profiles]) / 1e3
            cloud = pv.PolyData(pts)
            cloud["pressure [kPa]"] = kpa
            plotter.add_mesh(
                cloud,
                scalars="pressure [kPa]",
                clim=(0.0, top / 1e3),
                cmap="viridis",
                point_size=7,
                scalar_bar_args={"fmt": "%.0f", "n_labels": 3},
                render_points_as_spheres=True,
                show_scalar_bar=i == n - 1,
            )
        plotter.add_text(f"{model}: q = {q:.2f}", font_size=10)
        centre = 0.5 * (contact.jaws[0].origin + contact.jaws[1].origin) * 1e3
        plotter.camera.focal_point = centre
        view = np.array([0.45, -0.65, 0.62])  # from above, beside the grasp axis
        plotter.camera.position = centre + 2.2 * size * view
        plotter.camera.up = (0.0, 0.0, 1.0)
    if title:
        plotter.subplot(0, 0)
        plotter.add_text(title, position="lower_left", font_size=8)
    return save_screenshot(plotter, Path(path))
