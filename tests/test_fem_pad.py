"""Pad mesh and the condensed face compliance: exact against full solves."""

import numpy as np
import pytest
from skfem import condense, solve

from workbench.fem.elasticity import basis, stiffness
from workbench.fem.material import Material
from workbench.fem.pad import PadGeometry, condense_pad

GEOM = PadGeometry(width=0.01, length=0.016, thickness=0.004, nx=5, ny=8, nz=3)


def full_face_displacement(geom, material, f_face):
    """Reference: solve the whole layer for face forces f_face (3n,) node-major."""
    mesh = geom.mesh()
    K = stiffness(mesh, material)
    nodal = basis(mesh).nodal_dofs
    z = mesh.p[2]
    face = np.flatnonzero(np.isclose(z, geom.thickness))
    f = np.zeros(K.shape[0])
    f[nodal[:, face].T.ravel()] = f_face
    u = solve(*condense(K, f, D=nodal[:, np.isclose(z, 0)].ravel()))
    return u[nodal[:, face].T.ravel()]


def test_condensed_compliance_is_exact_symmetric_pd_and_scales_with_1_over_E():
    mat = Material(E=2.0e6, nu=0.499)
    pad = condense_pad(GEOM, mat, cache_dir=False)
    n = pad.face_nodes.size
    assert pad.compliance.shape == (3 * n, 3 * n)
    rng = np.random.default_rng(0)
    f = rng.standard_normal(3 * n)
    ref = full_face_displacement(GEOM, mat, f)
    np.testing.assert_allclose(pad.compliance @ f, ref, rtol=1e-9, atol=1e-12 * np.abs(ref).max())
    C = pad.compliance
    assert np.abs(C - C.T).max() <= 1e-12 * np.abs(C).max()
    assert np.linalg.eigvalsh(C).min() > 0
    # same nu, other E: exactly C / E (the cache stores E = 1)
    soft = condense_pad(GEOM, Material(E=5.0e5, nu=0.499), cache_dir=False)
    np.testing.assert_allclose(soft.compliance, C * 4.0, rtol=1e-12)
    # tangential coupling is kept: a normal load moves face nodes sideways (Poisson effect)
    k = n // 2
    u = C[:, 3 * k + 2]
    assert np.abs(u[0::3]).max() > 1e-3 * u[3 * k + 2]


def test_compliance_disk_cache(tmp_path):
    mat = Material(E=1.0e6, nu=0.45)
    first = condense_pad(GEOM, mat, cache_dir=tmp_path)
    assert first.seconds > 0 and not first.from_cache and len(list(tmp_path.glob("pad-*.npz"))) == 1
    again = condense_pad(GEOM, Material(E=3.0e6, nu=0.45), cache_dir=tmp_path)
    assert again.from_cache and again.seconds == first.seconds  # loaded, reports the build time
    np.testing.assert_allclose(again.compliance, first.compliance / 3.0, rtol=1e-12)
    other = condense_pad(GEOM, Material(E=1.0e6, nu=0.3), cache_dir=tmp_path)
    assert other.seconds > 0 and not other.from_cache  # nu is part of the key


def test_default_disk_cache_location_and_file_mode(tmp_path, monkeypatch):
    import os

    from workbench.fem.pad import pad_cache_dir

    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path))
    assert pad_cache_dir() == tmp_path
    mat = Material(E=1.0e6, nu=0.45)
    first = condense_pad(GEOM, mat)  # cache_dir=None: the default location (here the env override)
    files = list(tmp_path.glob("pad-*.npz"))
    assert not first.from_cache and len(files) == 1
    assert not list(tmp_path.glob(".*.tmp"))  # atomic: no temp file left behind
    umask = os.umask(0o022)
    os.umask(umask)
    assert files[0].stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's 0600
    again = condense_pad(GEOM, mat)
    assert again.from_cache
    assert np.array_equal(again.compliance, first.compliance)  # bit-identical
    # the key holds the code's digest: other code misses the file
    monkeypatch.setattr("workbench.fem.pad.code_digest", lambda *modules, **kw: "other-code")
    assert not condense_pad(GEOM, mat).from_cache
    assert len(list(tmp_path.glob("pad-*.npz"))) == 2


def test_cache_can_be_disabled_and_survives_a_corrupt_file(tmp_path, monkeypatch):
    from workbench.fem.pad import pad_cache_dir

    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path))
    mat = Material(E=1.0e6, nu=0.45)
    off = condense_pad(GEOM, mat, cache_dir=False)
    assert not off.from_cache and not list(tmp_path.iterdir())
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", "off")
    assert pad_cache_dir() is None
    monkeypatch.delenv("WORKBENCH_CACHE_DIR")
    default = pad_cache_dir()
    assert default.name == "pads" and default.parent.name == "nonplanar-workbench"
    assert pad_cache_dir(tmp_path / "x") == tmp_path / "x"
    with pytest.raises(ValueError, match="cache_dir must be None"):
        pad_cache_dir(3)
    # a truncated cache file is rebuilt (and replaced), not trusted
    first = condense_pad(GEOM, mat, cache_dir=tmp_path)
    (path,) = tmp_path.glob("pad-*.npz")
    path.write_bytes(path.read_bytes()[:100])
    rebuilt = condense_pad(GEOM, mat, cache_dir=tmp_path)
    assert not rebuilt.from_cache
    np.testing.assert_allclose(rebuilt.compliance, off.compliance, rtol=1e-12)
    assert condense_pad(GEOM, mat, cache_dir=tmp_path).from_cache
    np.testing.assert_allclose(first.compliance, off.compliance, rtol=1e-12)


@pytest.mark.jit_only("over 15 s as pure Python")
def test_uniform_pressure_on_a_thin_layer_matches_the_confined_modulus():
    # a thin bonded layer (h << w) under uniform normal pressure deforms like a confined column:
    # u_z = p h / M with M = (1 - nu) E / ((1 + nu)(1 - 2 nu)), away from the free edges
    geom = PadGeometry(width=0.06, length=0.06, thickness=0.002, nx=30, ny=30, nz=2)
    mat = Material(E=1.0e6, nu=0.3)
    pad = condense_pad(geom, mat, cache_dir=False)
    x, y = pad.face_xy.T
    dx, dy = geom.width / geom.nx, geom.length / geom.ny
    # consistent nodal forces of a uniform pressure p on a bilinear face: p * tributary area
    area = (
        dx
        * dy
        * np.where(np.isclose(np.abs(x), geom.width / 2), 0.5, 1.0)
        * np.where(np.isclose(np.abs(y), geom.length / 2), 0.5, 1.0)
    )
    p = 1.0e4
    f = np.zeros(3 * x.size)
    f[2::3] = -p * area  # pressing the face towards the jaw
    uz = (pad.compliance @ f)[2::3]
    center = (np.abs(x) < 0.01) & (np.abs(y) < 0.01)
    expected = -p * geom.thickness / mat.p_wave
    assert uz[center].mean() == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("kw", [{"thickness": 0.0}, {"width": -1.0}, {"nz": 0}])
def test_bad_geometry(kw):
    with pytest.raises(ValueError, match="must be"):
        PadGeometry(**kw)


def test_graded_axes():
    from workbench.fem.pad import graded_half_axis

    ax = graded_half_axis(0.02, 0.003, 0.0002, 1.3)
    assert ax[0] == 0.0 and ax[-1] == pytest.approx(0.02)
    steps = np.diff(ax)
    assert (steps > 0).all()
    np.testing.assert_allclose(steps[ax[1:] <= 0.003], 0.0002)  # uniform in the fine zone
    assert steps[-2] > 5 * 0.0002  # graded outside
    g = PadGeometry(0.04, 0.04, 0.02, grading=(0.003, 0.0005, 1.3))
    x, y, z = g.axes()
    np.testing.assert_allclose(x, -x[::-1])  # symmetric about the face center
    assert z[0] == pytest.approx(0.0) and z[-1] == pytest.approx(0.02)
    assert np.diff(z)[-1] == pytest.approx(0.0005)  # fine just below the contact face


def test_patch_condensation_is_the_sub_block_of_the_full_face():
    mat = Material(E=1.0e6, nu=0.45)
    full = condense_pad(GEOM, mat, cache_dir=False)
    patch = condense_pad(GEOM, mat, patch_radius=0.003, cache_dir=False)
    assert 0 < patch.face_nodes.size < full.face_nodes.size
    idx = np.searchsorted(full.face_nodes, patch.face_nodes)
    assert np.array_equal(full.face_nodes[idx], patch.face_nodes)
    dofs = (3 * idx[:, None] + np.arange(3)).ravel()
    np.testing.assert_allclose(patch.compliance, full.compliance[np.ix_(dofs, dofs)], rtol=1e-9, atol=1e-18)
