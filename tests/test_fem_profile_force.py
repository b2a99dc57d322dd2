"""FEM profiles carry the solved force (fem/extract.py, issue 11).

``λ_i`` is the magnitude of node i's contact force along the obstacle normal
``n_i`` (fem/contact.py), so the profile must have ``F = Σ p a = Σ λ`` and a
normal-wrench force ``−Σ p a n`` equal to the solution's ``−Σ λ_i n_i``.  The
second holds up to the spread of the normals within an element: with θ the
largest angle between two corner normals of a loaded quad, each element's
force-weighted mean of unit normals has length ≥ cos θ, so
``‖w⊥_f − (−Σ λ n)‖ ≤ (1 − cos θ) Σ λ`` (a bound from the solution alone).
"""

from pathlib import Path

import numpy as np
import pytest

from workbench.fem import press
from workbench.fem.contact import ContactSolution
from workbench.fem.extract import extract_profile, face_grid
from workbench.fem.material import Material
from workbench.fem.obstacles import MeshObstacle, Plane, Sphere
from workbench.fem.pad import PadFace, PadGeometry

DELTAS_MM = [0.1, 0.25, 0.5, 1.0, 2.0, 3.0]
MAT = Material(E=1.0e6, nu=0.45)  # as fem-fitting
BOTTLE = (
    Path(__file__).resolve().parents[2]
    / "shared/data/thesis_objects/0006_bottle-gen_smoothie_150x040x040-04.obj"
)


@pytest.fixture(scope="module")
def pad_cache(request, tmp_path_factory):
    # the default 20 x 40 x 5 mm pad condenses in 20-70 s: keep it in pytest's cache
    # (.pytest_cache, per checkout) so only the first run pays for it
    cache = getattr(request.config, "cache", None)
    return cache.mkdir("fem-pads") if cache is not None else tmp_path_factory.mktemp("fem-pads")


def _spread_bound(sol: ContactSolution, face_xy: np.ndarray) -> float:
    """1 − cos θ, θ the largest angle between two corner normals of a loaded quad."""
    quads, _ = face_grid(face_xy)
    q = quads[(sol.lam[quads] > 0).any(axis=1)]
    nn = sol.normals[q]  # (m, 4, 3)
    return float(1.0 - np.einsum("eij,ekj->eik", nn, nn).min())


def _check_force(prof, sol, face_xy):
    total = sol.lam.sum()
    assert total > 0
    # Σ p a = Σ λ: the bound, and the exactness the construction gives
    assert abs(prof.F - total) / total <= 5e-3
    assert prof.F == pytest.approx(total, rel=1e-12)
    # normal wrench force = the solution's force on the object −Σ λ_i n_i (independent sum)
    f_sol = -(sol.lam[:, None] * sol.normals).sum(axis=0)
    np.testing.assert_allclose(sol.force_vector, f_sol, rtol=1e-14, atol=1e-14 * total)
    bound = _spread_bound(sol, face_xy)
    err = np.linalg.norm(prof.normal_wrench[:3] - f_sol)
    assert err <= bound * total
    # λ is along the obstacle normal, not the press axis: on a curved object the
    # resultant is shorter than Σ λ, and the profile's is too
    assert np.linalg.norm(prof.normal_wrench[:3]) < total


@pytest.fixture(scope="module")
def sphere_press(pad_cache):
    h = PadGeometry().thickness
    sphere = Sphere((0.0, 0.0, h + 0.02), 0.02)
    return press(PadGeometry(), MAT, sphere, [d * 1e-3 for d in DELTAS_MM], cache_dir=pad_cache)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("delta_mm", DELTAS_MM)
def test_default_pad_on_a_sphere_profile_carries_the_solved_force(sphere_press, delta_mm):
    res = sphere_press
    d = delta_mm * 1e-3
    sol = res[d]
    prof = res.profile(d)  # press, then extract the profile
    _check_force(prof, sol, res.pad.face_xy)
    # R = 20 mm, 1 mm face spacing: the face nodes lie R - δ from the sphere's center, so
    # two corner normals of a quad (diagonal √2 mm) differ by at most √2 mm / (R - δ)
    assert _spread_bound(sol, res.pad.face_xy) <= 1 - np.cos(np.sqrt(2) * 1e-3 / (0.02 - d))
    # axisymmetric contact: the resultant is along the press axis
    assert np.abs(prof.normal_wrench[:2]).max() <= 1e-12 * sol.force
    assert prof.normal_wrench[2] > 0  # pushes the object away from the jaw
    np.testing.assert_allclose(prof.pressure_center[:2], 0.0, atol=1e-9)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_press_result_is_the_solutions_plus_pad(sphere_press):
    res = sphere_press
    assert sorted(res) == [d * 1e-3 for d in DELTAS_MM]  # still the {delta: solution} dict
    assert all(isinstance(s, ContactSolution) for s in res.values())
    assert res.fidelity == "condensed" and res.pad.face_xy.shape[0] == res[1e-3].lam.size
    profs = res.profiles()
    assert [p.F for p in profs.values()] == pytest.approx([s.force for s in res.values()], rel=1e-12)
    with pytest.raises(ValueError, match="no solution at delta"):
        res.profile(4e-3)
    with pytest.raises(ValueError, match="face_xy"):
        extract_profile(object(), res[1e-3], res.obstacle)
    small = PadFace.of(PadGeometry(0.01, 0.01, 0.003, 4, 4, 2), MAT)
    with pytest.raises(ValueError, match="face nodes but the solution has"):
        extract_profile(small, res[1e-3], res.obstacle)


@pytest.fixture(scope="module")
def bottle_press(pad_cache):
    if not BOTTLE.exists():
        pytest.skip(f"thesis objects not available ({BOTTLE.parent})")
    obs = MeshObstacle(BOTTLE)  # metres
    # the bottle's outermost side point (max x) onto the pad face center: x -> -z
    top = obs.mesh.vertices[np.argmax(obs.mesh.vertices[:, 0])]
    h = PadGeometry().thickness
    T = np.eye(4)
    T[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    T[:3, 3] = [-top[2], -top[1], h + top[0]]
    placed = obs.transformed(T, facing=(0, 0, -1))  # thin wall: one-sided distance
    return press(PadGeometry(), MAT, placed, [d * 1e-3 for d in DELTAS_MM], cache_dir=pad_cache)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
@pytest.mark.parametrize("delta_mm", DELTAS_MM)
def test_default_pad_on_a_thesis_bottle_profile_carries_the_solved_force(bottle_press, delta_mm):
    d = delta_mm * 1e-3
    prof = bottle_press.profile(d)
    _check_force(prof, bottle_press[d], bottle_press.pad.face_xy)
    assert (prof.normals[:, 2] < 0).all()  # outward from the bottle, towards the jaw


def test_uniform_cauchy_pressure_is_reproduced_exactly():
    """Nodal forces of a uniform pressure p0 on the *deformed* face (face stretched
    in-plane by s: deformed tributary areas = s² × undeformed) give p = p0 on every
    element, areas s² dx dy and F = p0 s² × face area."""
    geom = PadGeometry(0.008, 0.012, 0.002, 4, 6, 2)
    face = PadFace.of(geom, MAT)
    _, area0 = face_grid(face.face_xy)  # undeformed tributary areas
    s, p0, h = 1.1, 2.5e4, geom.thickness
    n = face.face_xy.shape[0]
    x = np.column_stack([s * face.face_xy, np.full(n, h)])
    normals = np.tile([0.0, 0.0, -1.0], (n, 1))
    u = x - np.column_stack([face.face_xy, np.full(n, h)])
    sol = ContactSolution(p0 * s**2 * area0, normals, u, x, 1, "synthetic", 0.0)
    prof = extract_profile(face, sol, Plane((0, 0, h), (0, 0, -1)))
    np.testing.assert_allclose(prof.pressures, p0, rtol=1e-12)
    np.testing.assert_allclose(prof.areas, s**2 * 0.002 * 0.002, rtol=1e-12)
    assert prof.F == pytest.approx(p0 * s**2 * geom.width * geom.length, rel=1e-12)
    np.testing.assert_allclose(prof.normal_wrench, [0, 0, prof.F, 0, 0, 0], atol=1e-12 * prof.F)


@pytest.mark.jit_only("its fixtures take over 15 s as pure Python")
def test_vtu_round_trip_carries_normals_and_areas(sphere_press, tmp_path):
    import meshio

    from workbench import ContactProfile

    prof = sphere_press.profile(1e-3)
    path = tmp_path / "profile.vtu"
    prof.to_meshio().write(path)
    back = meshio.read(path)
    for name, ref in (("pressure", prof.pressures), ("normals", prof.normals), ("areas", prof.areas)):
        (arr,) = back.cell_data[name]
        assert arr.shape == ref.shape
        np.testing.assert_allclose(arr, ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(back.points, prof.vertices, rtol=1e-12, atol=0)
    again = ContactProfile.from_meshio(back)
    np.testing.assert_allclose(again.pressures, prof.pressures, rtol=1e-12)
    # the exported normals and areas are read back, so F = Σ λ survives the round trip
    # (rebuilt from the quads it was 0.07 % off, areas up to 6 %: a new-user trial)
    np.testing.assert_allclose(again.areas, prof.areas, rtol=1e-12)
    np.testing.assert_allclose(again.normals, prof.normals, rtol=0, atol=1e-12)
    assert again.F == pytest.approx(sphere_press[1e-3].force, rel=1e-12)
    # a profile whose normals/areas are its faces' (from_mesh): from_meshio rebuilds them to 1e-12
    flat = ContactProfile.from_mesh(back.points, back.cells[0].data, prof.pressures)
    flat.to_meshio().write(tmp_path / "flat.vtu")
    rt = ContactProfile.from_meshio(meshio.read(tmp_path / "flat.vtu"))
    np.testing.assert_allclose(rt.areas, flat.areas, rtol=1e-12)
    np.testing.assert_allclose(rt.normals, flat.normals, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="no mesh"):
        ContactProfile(prof.centers, prof.normals, prof.areas, prof.pressures).to_meshio()


def test_millimetre_inputs_raise_instead_of_pressing_nothing(pad_cache):
    """A new-user trial: δ = 1.0 meant as 1 mm moved the jaw through a 40 mm sphere and
    returned zero force; a sphere given in millimetres did the same."""
    h = PadGeometry().thickness
    with pytest.raises(ValueError, match="metres"):
        press(PadGeometry(), MAT, Sphere((0.0, 0.0, h + 0.02), 0.02), [0.25, 1.0], cache_dir=pad_cache)
    with pytest.raises(ValueError, match="20 mm = 0.02"):
        Sphere((0.0, 0.0, 25.0), 20.0)
    assert Sphere((0.0, 0.0, 50.0), 50.0, allow_scale=True).radius == 50.0  # a deliberate giant
