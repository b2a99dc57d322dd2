"""workbench.sources.jaws: the parallel-jaw checks every jaw-profile source passes — the
force reading, the pad, the grasp dict, the jaw frame, the scaling to a force-sensor
reading along the grasp axis (thesis §4.1.3.2) and the checked jaw profile."""

import numpy as np
import pytest

from workbench import ContactProfile, config
from workbench.sources.jaws import (
    check_grasp,
    check_jaw_force,
    check_pad,
    checked_jaw_profile,
    jaw_frame,
    with_axis_force,
)


def _tilted_patch(point, approach, tilt=0.3, n=5):
    """n × n elements around ``point`` whose outward normals are −approach tilted by ±tilt
    (rad) about z in alternate elements: the normal force on the object is Σ p a (−n), and
    cos(tilt) of every element's force lies along the approach (approach ±x only)."""
    a = np.asarray(approach, float)
    g = np.linspace(-0.004, 0.004, n)
    Y, Z = np.meshgrid(g, g)
    centers = np.asarray(point, float) + np.c_[np.zeros(n * n), Y.ravel(), Z.ravel()]
    sign = np.where(np.arange(n * n) % 2 == 0, 1.0, -1.0)
    c, s = np.cos(tilt), np.sin(tilt) * sign
    normals = np.c_[np.full(n * n, -a[0] * c), -a[0] * s, np.zeros(n * n)]  # approach along ±x
    areas = np.full(n * n, 1e-6)
    pressures = np.linspace(1e4, 3e4, n * n)
    return ContactProfile(centers, normals, areas, pressures)


def test_check_jaw_force_takes_finite_positive_numbers_only():
    for good in (10, 0.5, np.float64(3.0), np.int64(2)):
        check_jaw_force(good)
    for bad in (True, np.bool_(True), "10", None, 0.0, -1.0, np.nan, np.inf, [10.0]):
        with pytest.raises(
            ValueError, match=r"force \(each jaw's reading \[N\]\) must be a (jaw force in|number)"
        ):
            check_jaw_force(bad)


def test_check_pad_takes_two_finite_positive_sizes():
    for good in ((0.02, 0.04), [0.01, 0.01], np.array([0.03, 0.05])):
        check_pad(good)
    for bad in (
        (0.02,),
        (0.02, 0.04, 0.005),
        (0.0, 0.04),
        (-0.02, 0.04),
        (np.nan, 0.04),
        (np.inf, 1),
        "ab",
        None,
    ):
        with pytest.raises(
            ValueError, match=r"pad must be the jaw face \(width, length\) \[m\], two numbers > 0"
        ):
            check_pad(bad)


def test_check_grasp_normalises_the_axis_and_names_what_is_missing():
    p1, p2, axis = check_grasp({"p1": [0.03, 0, 0.04], "p2": [-0.03, 0, 0.12], "axis": [-3.0, 0.0, 4.0]})
    np.testing.assert_allclose(axis, [-0.6, 0.0, 0.8], rtol=1e-15)  # (−3, 0, 4) / 5, along p2 − p1
    assert p1.tolist() == [0.03, 0, 0.04] and p2.tolist() == [-0.03, 0, 0.12]
    # an axis 45 deg off the line through both contacts: a hand-made grasp dict (new-user trial)
    with pytest.raises(ValueError, match=r"45.0 deg from the line p1 → p2 .* pass axis = \(p2 - p1\)"):
        check_grasp({"p1": [0, -0.02, 0], "p2": [0, 0.02, 0], "axis": [0, 1, 1]})
    with pytest.raises(ValueError, match="p1 and p2 swapped"):
        check_grasp({"p1": [0.03, 0, 0], "p2": [-0.03, 0, 0], "axis": [1, 0, 0]})
    with pytest.raises(ValueError, match=r"'p1', 'p2'.*and 'axis'.*got \['p1', 'p2'\]"):
        check_grasp({"p1": [0, 0, 0], "p2": [1, 0, 0]})
    with pytest.raises(ValueError, match="got list"):
        check_grasp([[0, 0, 0], [1, 0, 0], [1, 0, 0]])
    for bad in ({"axis": [1, 0]}, {"p1": [0, 0]}):
        with pytest.raises(ValueError, match=r"must be \(3,\) vectors, axis non-zero"):
            check_grasp({"p1": [0, 0, 0], "p2": [1, 0, 0], "axis": [1, 0, 0], **bad})


def test_check_grasp_refuses_a_zero_axis_non_finite_points_and_a_zero_width_by_name():
    ok = {"p1": [-0.02, 0.0, 0.0], "p2": [0.02, 0.0, 0.0], "axis": [1.0, 0.0, 0.0]}
    # a zero axis read as "up is parallel to the grasp axis (0, 0, 0)" with a numpy
    # divide warning; it gets its own message, with the axis the points give
    with pytest.raises(
        ValueError, match=r"grasp axis must be a direction .* a zero vector.* = \[1.0, 0.0, 0.0\]"
    ):
        check_grasp({**ok, "axis": [0.0, 0.0, 0.0]})
    # NaN in p1 failed deep in scipy's cKDTree; each vector is named
    for name in ("p1", "p2", "axis"):
        bad = list(ok[name])
        bad[1] = np.nan if name != "axis" else np.inf
        with pytest.raises(ValueError, match=rf"grasp {name} must be finite .*got \["):
            check_grasp({**ok, name: bad})
    # p1 == p2 was simulated and reported as a jaw that touched nothing
    for width in (0.0, 5e-5):
        with pytest.raises(ValueError, match=r"p1 and p2 must be two contact points at least 0.1 mm apart"):
            check_grasp({**ok, "p2": [-0.02 + width, 0.0, 0.0]})
    # the neighbours: a 0.2 mm grasp (a thin wall) passes with its axis as given
    p1, p2, axis = check_grasp({**ok, "p2": [-0.0198, 0.0, 0.0]})
    assert np.linalg.norm(p2 - p1) == pytest.approx(2e-4) and axis.tolist() == [1.0, 0.0, 0.0]
    # the narrowest width is config's, read at call time
    with config.override(min_grasp_width_m=5e-4):
        with pytest.raises(ValueError, match=r"at least 0.5 mm apart"):
            check_grasp({**ok, "p2": [-0.0198, 0.0, 0.0]})


def test_jaw_frame_is_right_handed_with_the_length_axis_from_up():
    """approach x, up z: (x, z × x = y, z); an up tilted towards the approach keeps only its
    perpendicular part; (a, e1, e2) is orthonormal with e1 × e2 = a."""
    a, e1, e2 = jaw_frame([2.0, 0, 0], [0, 0, 1])
    np.testing.assert_allclose(np.array([a, e1, e2]), [[1, 0, 0], [0, 1, 0], [0, 0, 1]], atol=1e-15)
    a, e1, e2 = jaw_frame([1.0, 0, 0], [1.0, 0, 1.0])
    np.testing.assert_allclose(e2, [0, 0, 1], atol=1e-15)
    rng = np.random.default_rng(4)
    for _ in range(10):
        a, e1, e2 = jaw_frame(rng.normal(size=3), rng.normal(size=3))
        np.testing.assert_allclose(np.array([a, e1, e2]) @ np.array([a, e1, e2]).T, np.eye(3), atol=1e-14)
        np.testing.assert_allclose(np.cross(e1, e2), a, atol=1e-14)
    with pytest.raises(ValueError, match="up must not be parallel to the approach"):
        jaw_frame([0, 0, 1.0], [0, 0, -2.0])


def test_with_axis_force_sets_the_reading_along_the_axis():
    """The reading is |Σ p a (−n) · axis| = cos(tilt) Σ p a for the tilted patch; scaled to
    ``force`` it is force, and every pressure is multiplied by one factor."""
    prof = _tilted_patch([0.03, 0, 0], [-1.0, 0, 0])
    reading = np.cos(0.3) * (prof.pressures * prof.areas).sum()
    for axis in ([1.0, 0, 0], [-2.0, 0, 0]):  # either sign and any length of the grasp axis
        out = with_axis_force(prof, axis, 5.0)
        np.testing.assert_allclose(out.pressures, prof.pressures * 5.0 / reading, rtol=1e-12)
        assert abs(-(out.pressures * out.areas) @ out.normals @ [1.0, 0, 0]) == pytest.approx(5.0, rel=1e-12)
    with pytest.raises(ValueError, match="no normal force along the axis"):
        with_axis_force(prof, [0, 0, 1.0], 5.0)


def test_checked_jaw_profile_scales_a_profile_at_its_jaw_and_refuses_others():
    point, approach, pad = np.array([0.03, 0, 0]), np.array([-1.0, 0, 0]), (0.02, 0.04)
    prof = _tilted_patch(point, approach)
    out = checked_jaw_profile(prof, point, approach, 8.0, pad)
    assert out.normal_wrench[:3] @ approach == pytest.approx(8.0, rel=1e-12)
    with pytest.raises(ValueError, match="profiles must be ContactProfile objects, one per jaw; got dict"):
        checked_jaw_profile({"centers": prof.centers}, point, approach, 8.0, pad)
    with pytest.raises(ValueError, match="pad must be"):
        checked_jaw_profile(prof, point, approach, 8.0, (0.02, 0.0))
    # the pressure centre Σ p a c / Σ p a must lie in the pad's footprint: within half its
    # diagonal √(0.02² + 0.04²) / 2 = 22.4 mm (× 1.1, config.TOL.jaw_profile_plane_rtol) of the
    # jaw point in the pad plane — a jaw point 30 mm away along y is refused, 20 mm accepted
    centre = (prof.pressures * prof.areas) @ prof.centers / (prof.pressures * prof.areas).sum()
    far = point + [0, 0.03, 0]
    off = np.linalg.norm(centre - far)
    assert off > 1.1 * np.hypot(*pad) / 2 > np.linalg.norm(centre - point - [0, 0.02, 0])
    with pytest.raises(ValueError, match=rf"pressure centre is {off * 1e3:.3g} mm from its jaw's contact"):
        checked_jaw_profile(prof, far, approach, 8.0, pad)
    checked_jaw_profile(prof, point + [0, 0.02, 0], approach, 8.0, pad)
    # along the approach at most 0.5 (config.TOL.jaw_profile_depth_rtol) of that half-diagonal,
    # 11.2 mm, deeper than the jaw point: a jaw point 15 mm outside the object (the profile of a
    # narrower object) is refused, 10 mm accepted; one 15 mm inside it (a pad stopped by a rim) too
    with pytest.raises(ValueError, match=r"pressure centre is 15 mm into the object from its jaw's contact"):
        checked_jaw_profile(prof, point - 0.015 * approach, approach, 8.0, pad)
    checked_jaw_profile(prof, point - 0.01 * approach, approach, 8.0, pad)
    checked_jaw_profile(prof, point + 0.015 * approach, approach, 8.0, pad)
    flipped = ContactProfile(prof.centers, -prof.normals, prof.areas, prof.pressures)
    with pytest.raises(ValueError, match=r"would pull the object .*normals must point out of the object"):
        checked_jaw_profile(flipped, point, approach, 8.0, pad)
