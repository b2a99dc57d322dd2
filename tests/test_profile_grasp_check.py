"""Given jaw profiles are checked against the grasp they are used for: a profile
that records its source (ContactProfile.source, a ProfileSource: the FEM pad's reading and the
largest it reaches) is not scaled to a reading the source cannot produce, and is warned about
when scaled far from the reading it was made at (the FEM pad's contact grows with force); and
its pressure centre must lie in the pad's footprint around the jaw point and near it along the
approach (config.TOL.jaw_profile_plane_rtol, jaw_profile_depth_rtol), not merely within the
pad's diagonal."""

import warnings

import numpy as np
import pytest
import trimesh

from workbench import ContactProfile, config
from workbench.grasp import Jaws, ModelOptions, Task, evaluate_grasp
from workbench.profile import ProfileSource
from workbench.sources.jaws import with_axis_force

MU, FORCE = 0.5, 10.0
R = 0.03  # the cylinder's radius [m]
FACE = (0.016, 0.024)  # the pad's face (width, length) [m]: half its diagonal is 14.4 mm
AXIS = np.array([1.0, 0.0, 0.0])
GRASP = {"p1": -R * AXIS, "p2": R * AXIS, "axis": AXIS}
W = np.array([0.0, 0.0, -2.0, 0.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def fem():
    """A soft (E = 0.2 MPa) 4 mm pad, 8 x 12 face elements, and its two jaws' profiles at
    10 N on a cylinder grasped along x (the cylinder and pad made once)."""
    from workbench.fem.material import Material
    from workbench.fem.pad import PadGeometry, condense_pad
    from workbench.sources.fem_jaw import fem_jaw_profiles

    geom = PadGeometry(width=FACE[0], length=FACE[1], thickness=0.004, nx=8, ny=12, nz=2)
    pad = condense_pad(geom, Material(E=2.0e5), cache_dir=False)
    cyl = trimesh.creation.cylinder(radius=R, height=0.12, sections=128)
    return pad, cyl, fem_jaw_profiles(cyl, GRASP, FORCE, pad=pad)


def _evaluate(profiles, force=FORCE, grasp=GRASP):
    jaws, opts = Jaws(force=force, pad=FACE), ModelOptions(model="soft_point", mu=MU)
    return evaluate_grasp(None, grasp, Task(w_ext=W), jaws=jaws, options=opts, profiles=profiles)


def test_an_fem_profile_records_the_readings_its_pad_can_produce(fem):
    """The recorded range is the pad's own: at 0.99 of its top fem_jaw_profile still presses
    the pad there, at 1.01 it refuses as the layer is spent."""
    from workbench.sources.fem_jaw import fem_jaw_profile

    pad, cyl, jaws = fem
    for prof in jaws:
        src = prof.source
        assert src.name == "fem_pad" and src.force == FORCE and not src.linear
        lo, hi = src.force_range
        assert lo == 0.0 and 4 * FORCE < hi < 50 * FORCE  # ~80 N for this soft layer
    hi = jaws[0].source.force_range[1]
    top = fem_jaw_profile(cyl, GRASP["p1"], AXIS, 0.99 * hi, pad=pad)
    assert top.normal_wrench[:3] @ AXIS == pytest.approx(0.99 * hi, rel=1e-9)
    assert top.source.force_range[1] == pytest.approx(hi, rel=1e-9)  # the same pad, the same reach
    with pytest.raises(ValueError, match="reaches only"):
        fem_jaw_profile(cyl, GRASP["p1"], AXIS, 1.01 * hi, pad=pad)


def test_a_reading_beyond_the_source_is_refused_and_one_far_from_it_warned(fem):
    _, _, jaws = fem
    hi = min(p.source.force_range[1] for p in jaws)
    with pytest.raises(
        ValueError, match=r"outside what the profile's source can produce: fem_pad made it at 10 N"
    ):
        _evaluate(jaws, force=1.2 * hi)
    # within the range but twice the reading the pad was pressed to: scaled, with a warning
    with pytest.warns(UserWarning, match=r"fem_pad profile made at 10 N is scaled to 20 N \(x2\)"):
        ev = _evaluate(jaws, force=2 * FORCE)
    for prof, made in zip(ev.profiles, jaws, strict=True):
        assert abs(prof.normal_wrench[:3] @ AXIS) == pytest.approx(2 * FORCE, rel=1e-12)
        assert prof.source is made.source  # the distribution is still the one made at 10 N
    # 1.2 x is within config.TOL.profile_force_ratio_warn (1.331): silent; read at call time
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _evaluate(jaws, force=1.2 * FORCE)
        _evaluate(jaws, force=FORCE / 1.2)
    with config.override(profile_force_ratio_warn=1.1):
        with pytest.warns(UserWarning, match=r"config.TOL.profile_force_ratio_warn = 1.1"):
            _evaluate(jaws, force=1.2 * FORCE)


def test_profiles_without_a_source_or_of_a_linear_one_scale_freely():
    """A closed-form scene's profiles (no source) and a linear source's (REACH-like, pressures
    proportional to the reading) are scaled to any reading without a word; a linear source's
    range still bounds it."""
    from workbench.sources.scenes import elliptic_cylinder_grasp

    grasp = {"p1": [R, 0.0, 0.0], "p2": [-R, 0.0, 0.0], "axis": [-1.0, 0.0, 0.0]}
    jaws = elliptic_cylinder_grasp(force=FORCE, n_elements=100)
    assert all(p.source is None for p in jaws)
    linear = [p.with_source(ProfileSource("winkler", FORCE, (0.0, 100.0), linear=True)) for p in jaws]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for profiles, factor in ((jaws, 25.0), (linear, 8.0)):
            ev = _evaluate(profiles, force=factor * FORCE, grasp=grasp)
            assert abs(ev.profiles[0].normal_wrench[0]) == pytest.approx(factor * FORCE, rel=1e-12)
    with pytest.raises(ValueError, match=r"reaches \[0, 100\] N"):
        _evaluate(linear, force=15 * FORCE, grasp=grasp)


def test_profiles_of_another_grasp_position_are_refused(fem):
    """The z = 0 profiles used for the same grasp 30 mm higher lie 30 mm from the jaw points in
    the pad plane, beyond the footprint (14.4 mm x 1.1); 10 mm higher they are within it.  Jaws
    placed 10 mm wider than the object (a grasp of another width) put them 10 mm into the
    object along the approach, beyond 0.5 x 14.4 = 7.2 mm; 5 mm wider is within it, and 10 mm
    narrower too (towards the jaw is where a pad stopped by a rim presses)."""
    _, _, jaws = fem
    up = np.array([0.0, 0.0, 1.0])

    def moved(dz=0.0, wider=0.0):
        return {
            "p1": GRASP["p1"] + dz * up - wider * AXIS,
            "p2": GRASP["p2"] + dz * up + wider * AXIS,
            "axis": AXIS,
        }

    with pytest.raises(
        ValueError, match=r"pressure centre is 30 mm from its jaw's contact point .* in the pad plane"
    ):
        _evaluate(jaws, grasp=moved(dz=0.03))
    assert _evaluate(jaws, grasp=moved(dz=0.01)).resisted
    with pytest.raises(ValueError, match=r"is 10.\d mm into the object from its jaw's contact point"):
        _evaluate(jaws, grasp=moved(wider=0.01))
    assert _evaluate(jaws, grasp=moved(wider=0.005)).resisted
    assert _evaluate(jaws, grasp=moved(wider=-0.01)).resisted
    with config.override(jaw_profile_depth_rtol=0.3):  # 4.3 mm: read at call time
        with pytest.raises(ValueError, match=r"config.TOL.jaw_profile_depth_rtol = 0.3"):
            _evaluate(jaws, grasp=moved(wider=0.005))


def test_provenance_follows_the_distribution():
    """Rigid motions, normalisation and scaling keep a profile's source (the same distribution);
    new pressures drop it unless one is given; a source must hold its own reading."""
    c = np.array([[0.0, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]])
    n = np.tile([-1.0, 0.0, 0.0], (3, 1))
    src = ProfileSource("fem_pad", 10.0, (0.0, 80.0))
    prof = ContactProfile(c, n, [1e-6] * 3, [1e4, 2e4, 3e4], source=src)
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert prof.transformed(turn, [0.1, 0, 0]).source is src
    assert prof.normalized().source is src and prof.in_contact_frame().source is src
    doubled = prof.scaled(2.0)
    assert doubled.source is src and doubled.F == pytest.approx(2 * prof.F, rel=1e-15)
    assert with_axis_force(prof, [1.0, 0, 0], 12.0).source is src
    assert prof.with_pressures([1.0, 1.0, 1.0]).source is None
    assert prof.with_source(None).source is None
    for bad in (("x", 90.0, (0.0, 80.0)), ("x", 0.0, (0.0, 80.0)), ("x", 10.0, (20.0, 80.0))):
        with pytest.raises(ValueError, match="within force_range"):
            ProfileSource(*bad)
    with pytest.raises(ValueError, match="source must be a ProfileSource"):
        ContactProfile(c, n, [1e-6] * 3, [1.0] * 3, source={"force": 10.0})
    with pytest.raises(ValueError, match="factor must be"):
        prof.scaled(0.0)
