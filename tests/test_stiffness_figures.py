"""The stiffness-validation figures render offscreen on a synthetic cylinder."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.runner.stiffness_figures import MapStyle, plot_stiffness_validation, render_stiffness_maps


@pytest.fixture(scope="module")
def case():
    """A cylinder (r 3 cm, h 10 cm) and 12 made-up antipodal grasps: soft middle, stiff
    ends, one rigid measured grasp, one failed model grasp."""
    import trimesh

    mesh = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=24)
    rng = np.random.default_rng(0)
    n = 12
    z = np.linspace(-0.04, 0.04, n)
    a = rng.uniform(0, np.pi, n)
    p1 = np.c_[0.03 * np.cos(a), 0.03 * np.sin(a), z]
    L = np.r_[p1, np.c_[-p1[:, :2], z]]
    measured = 300 * np.exp(3 * np.abs(z) / 0.04)
    measured[0] = 8e10  # rigid
    predicted = measured * np.exp(rng.normal(0, 0.3, n))
    predicted[0] = 500.0
    predicted[1] = np.nan  # failed
    usable = np.arange(n) > 1
    train = usable & (np.arange(n) % 2 == 0)
    test = usable & ~train
    return mesh, L, measured, predicted, train, test


def test_validation_scatter(case, tmp_path):
    _, _, s, p, train, test = case
    path = plot_stiffness_validation(
        {"a": {"measured": s, "predicted": p, "train": train, "test": test}}, tmp_path / "v.png"
    )
    assert path.exists() and path.stat().st_size > 10_000


def test_validation_scatter_rejects_bad_input(case, tmp_path):
    _, _, s, p, train, test = case
    with pytest.raises(ValueError, match=r"predicted must be \(n,\) = \(12,\)"):
        plot_stiffness_validation(
            {"a": {"measured": s, "predicted": p[:-1], "train": train, "test": test}}, tmp_path / "v.png"
        )
    with pytest.raises(ValueError, match="boolean mask"):
        plot_stiffness_validation(
            {"a": {"measured": s, "predicted": p, "train": np.flatnonzero(train), "test": test}},
            tmp_path / "v.png",
        )
    with pytest.raises(ValueError, match="grasp 0 is in train/test"):  # the rigid one
        plot_stiffness_validation(
            {"a": {"measured": s, "predicted": p, "train": train | (np.arange(12) == 0), "test": test}},
            tmp_path / "v.png",
        )
    assert not (tmp_path / "v.png").exists()


def test_stiffness_maps(case, tmp_path):
    mesh, L, s, p, _, _ = case
    path = render_stiffness_maps(mesh.vertices, mesh.faces, L, s, p, tmp_path / "m.png", title="cylinder")
    assert path.exists() and path.stat().st_size > 20_000
    plain = render_stiffness_maps(
        mesh.vertices, mesh.faces, L, s, p, tmp_path / "p.png", style=MapStyle(surface=False)
    )
    assert plain.exists() and plain.stat().st_size > 10_000


def test_stiffness_maps_reject_mismatched_lengths(case, tmp_path):
    mesh, L, s, p, _, _ = case
    with pytest.raises(ValueError, match=r"locations must be \(2n, 3\) = \(24, 3\)"):
        render_stiffness_maps(mesh.vertices, mesh.faces, L[:-1], s, p, tmp_path / "m.png")
    with pytest.raises(ValueError, match=r"predicted must be \(n,\) = \(12,\)"):
        render_stiffness_maps(mesh.vertices, mesh.faces, L, s, p[:5], tmp_path / "m.png")
    with pytest.raises(ValueError, match=r"faces must be \(F, 3\) integer"):
        render_stiffness_maps(mesh.vertices, mesh.faces.astype(float), L, s, p, tmp_path / "m.png")
    assert not (tmp_path / "m.png").exists()


def test_map_style_checks_its_options():
    with pytest.raises(ValueError, match=r"rigid_threshold must be a stiffness > 0 \[N/m\].*got 0.0"):
        MapStyle(rigid_threshold=0.0)
    with pytest.raises(ValueError, match="model must be a str naming the prediction"):
        MapStyle(model=3)
