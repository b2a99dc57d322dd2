"""workbench.runner.viz: offscreen pyvista renders of contact profiles — the polydata of a meshed
profile (cell areas by VTK against the profile's), and the friction-arrow figure written as
a PNG of the requested size with non-trivial content.  Skips where pyvista cannot render
offscreen."""

import numpy as np
import pytest

from workbench import ContactProfile, mesh_profile
from workbench.sources.surface_catalog import S2, example_3_2_5


@pytest.fixture(scope="module")
def pv():
    """pyvista set up by workbench.runner.viz, or a skip when it cannot render offscreen here."""
    pytest.importorskip("pyvista")
    from workbench.runner.viz import _pyvista

    try:
        pv = _pyvista()
        plotter = pv.Plotter(off_screen=True, window_size=(40, 30))
        plotter.add_mesh(pv.Sphere())
        img = plotter.screenshot(return_img=True)
        plotter.close()
    except Exception as exc:  # no OpenGL / offscreen context on this machine
        pytest.skip(f"pyvista cannot render offscreen here: {exc}")
    if img is None or img.shape[:2] != (30, 40):
        pytest.skip("pyvista rendered no image offscreen")
    return pv


def test_profile_polydata_carries_the_mesh_and_pressures(pv):
    from workbench.runner.viz import profile_polydata

    prof = mesh_profile(S2, 120, pressure_scale=1e4)
    poly = profile_polydata(prof)
    assert poly.n_cells == len(prof) and poly.n_points == len(prof.vertices)
    np.testing.assert_array_equal(poly.cell_data["pressure"], prof.pressures)
    # VTK's own triangle areas agree with the profile's element areas
    np.testing.assert_allclose(poly.compute_cell_sizes()["Area"], prof.areas, rtol=1e-10)
    bare = ContactProfile(prof.centers, prof.normals, prof.areas, prof.pressures)
    with pytest.raises(ValueError, match="profile has no mesh"):
        profile_polydata(bare)


@pytest.mark.parametrize("surface", ["curved", "uniform"])
def test_friction_arrows_figure_is_written(pv, tmp_path, surface):
    """One panel per twist, each ``window_size`` wide: a (2 × 160) × 120 PNG; more than a
    background colour in every panel (the surface and arrows are drawn, over 2 % of it).  Example 3.2.5 has a
    uniform pressure (one colour, no colour bar); S2 with a quadratic pressure a colour map."""
    from PIL import Image

    from workbench.runner.viz import render_friction_arrows

    if surface == "uniform":
        prof = mesh_profile(example_3_2_5(), 80)
    else:
        prof = mesh_profile(S2, 80, pressure_scale=1e4)
        prof = prof.with_pressures(prof.pressures * (1 + prof.centers[:, 2] ** 2))
    twists = {"slide": np.array([0.0, 0, 1, 0, 0, 0]), "spin": np.array([0.0, 1, 0, 0, 0, 0])}
    path = render_friction_arrows(prof, twists, tmp_path / "f.png", title="t", window_size=(160, 120))
    assert path == tmp_path / "f.png"
    img = np.asarray(Image.open(path).convert("RGB")).astype(int)
    assert img.shape == (120, 320, 3)
    for panel in (img[:, :160], img[:, 160:]):
        colours, counts = np.unique(panel.reshape(-1, 3), axis=0, return_counts=True)
        background = colours[np.argmax(counts)]  # the commonest colour
        drawn = np.abs(panel - background).sum(axis=2) > 30
        assert 0.02 < drawn.mean() < 0.98, drawn.mean()
