"""workbench.grasp.sampling says what its long calls do: the candidates dropped per
reason come back with the grasps (``Grasps.dropped``, ``n_candidates``), fewer grasps than
asked for is a WARNING naming the reasons, and a progress bar can be asked for."""

import copy
import logging
import pickle
import re
import sys

import numpy as np
import pytest
import trimesh

from workbench.grasp.inputs import Jaws
from workbench.grasp.sampling import (
    DROP_REASONS,
    Grasps,
    GraspSampling,
    antipodal_grasps,
    edge_touch,
    horizontal_grasps,
)


def _adds_up(g: Grasps) -> None:
    assert set(g.dropped) == set(DROP_REASONS)
    assert len(g) + sum(g.dropped.values()) == g.n_candidates


def test_pad_edge_count_is_the_edge_check_of_every_antipodal_pair():
    """Same seed with and without the pad check: the pairs the pad check drops are exactly the
    pad=None grasps of which a jaw meets the surface at its pad edge (edge_touch applied here,
    one by one), the other reasons' counts are the same, and every candidate is accounted for."""
    cyl = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=48)
    m = 60  # n = max_samples: every candidate is tried
    every = antipodal_grasps(cyl, m, 0.5, GraspSampling(max_samples=m), jaws=None, seed=3)
    kept = antipodal_grasps(cyl, m, 0.5, GraspSampling(max_samples=m), seed=3)
    assert every.n_candidates == kept.n_candidates == m
    _adds_up(every)
    _adds_up(kept)
    edge = [
        edge_touch(cyl, g["p1"], g["axis"], (0, 0, 1), (0.02, 0.04), 1e-3)
        or edge_touch(cyl, g["p2"], -g["axis"], (0, 0, 1), (0.02, 0.04), 1e-3)
        for g in every
    ]
    assert every.dropped["pad_edge"] == 0
    assert kept.dropped["pad_edge"] == sum(edge) > 0
    assert [g["p1"].tolist() for g in kept] == [
        g["p1"].tolist() for g, e in zip(every, edge, strict=True) if not e
    ]
    for reason in set(DROP_REASONS) - {"pad_edge"}:
        assert kept.dropped[reason] == every.dropped[reason], reason
    # the cylinder's flat ends are 0.1 m apart, its round side 0.06 m: both drop reasons occur
    assert every.dropped["outside_cone"] > 0 and len(every) > 0


def test_every_candidate_too_wide_is_counted_and_warned(caplog):
    """Frictionless jaws (mu = 0) close along the surface normal exactly: on a 0.2 m cube every
    candidate spans 0.2 m, over a 0.1 m opening — all max_samples dropped as too wide."""
    cube = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    with caplog.at_level(logging.WARNING, logger="workbench.grasp.sampling"):
        g = antipodal_grasps(cube, 5, 0.0, GraspSampling(max_width=0.1, max_samples=40), jaws=None)
    assert list(g) == [] and g.n_candidates == 40
    assert g.dropped == {**dict.fromkeys(DROP_REASONS, 0), "too_wide": 40}
    (rec,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    msg = rec.getMessage()
    assert "0 of 5 grasps found among 40 candidates" in msg
    assert "40 too_wide" in msg and "max_width" in msg and "max_samples=40" in msg
    assert "pad_edge" not in msg  # only the reasons that occurred


def test_every_candidate_near_the_table():
    cube = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    under_top = GraspSampling(table_z=0.0249, max_samples=25)  # just under its top
    g = antipodal_grasps(cube, 3, 0.0, under_top, jaws=None)
    assert len(g) == 0 and g.dropped == {**dict.fromkeys(DROP_REASONS, 0), "near_table": 25}


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"table_z": 1.0}, "is above the object's top"),  # a table over the object
        ({"table_z": -50.0}, "farther below its bottom than its height"),  # mm
        ({"table_z": -0.025, "clearance": 10}, "probably in millimetres — pass 0.01"),
        # named as what it is, not a lever arm (a new-user trial); 0 is on the table, accepted
        ({"table_z": -0.025, "clearance": -1}, "must be a height above the table in [0, 0.1] m; got -1"),
        ({"max_width": 100}, "probably in millimetres — pass 0.1"),  # 100 mm meant
        ({"min_width": 0.05, "max_width": 0.02}, "min_width must be < max_width"),
        ({"max_width": -0.1}, "must be a gripper opening"),
        ({"up": (0, 0, 0)}, "up must be a non-zero"),
    ],
)
def test_arguments_that_would_drop_every_candidate_are_refused(kwargs, words):
    """A new user's trial: these returned 0 grasps, blaming too_wide / pad_edge, not the argument."""
    cube = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    with pytest.raises(ValueError, match=re.escape(words)):
        up = kwargs.pop("up", (0.0, 0.0, 1.0))
        antipodal_grasps(cube, 3, 0.5, GraspSampling(max_samples=25, **kwargs), jaws=Jaws(up=up))


def test_n_reached_stops_early_and_logs_no_warning(caplog):
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.03)
    with caplog.at_level(logging.INFO, logger="workbench.grasp.sampling"):
        g = antipodal_grasps(sphere, 5, 0.3, jaws=None, seed=0)
    assert len(g) == 5 and g.n_candidates == 5 + sum(g.dropped.values()) <= 100
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    assert any(f"5 kept of {g.n_candidates} candidates" in r.getMessage() for r in caplog.records)


def test_known_number_of_grid_lines_dropped_at_a_pad_edge_or_the_cone():
    """Lines through the centre of a 50 mm cube at 0°, 30°, ..., 150°: at 0° and 90° they meet
    two faces square on; at the other four the face is tilted 30° to the jaw, so the 20 mm wide
    pad first touches the face with its edge — pressed 1 mm past first touch the contact is a
    strip 1 mm / tan 30° = 1.7 mm wide along the pad's edge, its centre >= 10 - 1.7 mm from the
    grasp point, beyond the inner 3/4 (7.5 mm) — and lies outside a cone of atan 0.5 = 26.6°."""
    cube = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    for mu, reason in ((0.6, "pad_edge"), (0.5, "outside_cone")):
        g = horizontal_grasps(cube, [0.0], 6, mu)
        _adds_up(g)
        assert g.n_candidates == 6 and len(g) == 2
        assert g.dropped == {**dict.fromkeys(DROP_REASONS, 0), reason: 4}
        assert sorted(round(float(np.degrees(np.arctan2(x["axis"][1], x["axis"][0])))) for x in g) == [0, 90]
    assert len(horizontal_grasps(cube, [0.0], 6, 0.6, pad=None)) == 6


def test_grasps_is_the_list_it_was():
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.03)
    g = antipodal_grasps(sphere, 4, 0.3, jaws=None, seed=0)
    assert isinstance(g, list) and len(g) == 4 and g[0] is list(g)[0] and g[-1]["width"] > 0
    assert type(g[:2]) is list  # a slice is a plain list
    for back in (pickle.loads(pickle.dumps(g)), copy.deepcopy(g)):  # to a Dask worker and back
        assert isinstance(back, Grasps) and back.dropped == g.dropped and back.n_candidates == g.n_candidates
        assert [x["p1"].tolist() for x in back] == [x["p1"].tolist() for x in g]
    with pytest.raises(ValueError, match="dropped reasons must be keys of DROP_REASONS"):
        Grasps([], dropped={"edge": 1})


def test_bad_input_raises_before_the_work():
    """A pad in millimetres or a zero edge_depth used to make every pressed jaw raise inside the
    pad-edge check, which counted it as an edge touch: all grasps dropped, silently."""
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    with pytest.raises(ValueError, match="pad"):
        antipodal_grasps(sphere, 3, 0.3, jaws=Jaws(pad=(20, 40)))
    with pytest.raises(ValueError, match="edge_depth must be a closing > 0"):
        antipodal_grasps(sphere, 3, 0.3, GraspSampling(edge_depth=0.0))
    with pytest.raises(ValueError, match="pad"):
        horizontal_grasps(sphere, [0.0], 4, 0.3, pad=(20, 40))
    with pytest.raises(ValueError, match="pad"):
        edge_touch(sphere, np.array([0.03, 0, 0]), (-1, 0, 0), (0, 0, 1), (20, 40), 1e-3)
    with pytest.raises(ValueError, match="n must be an integer >= 1; got 0"):
        antipodal_grasps(sphere, 0, 0.3)
    with pytest.raises(ValueError, match="max_samples must be an integer >= 1; got 2.5"):
        antipodal_grasps(sphere, 3, 0.3, GraspSampling(max_samples=2.5))
    with pytest.raises(ValueError, match="progress must be True .* got 'yes'"):
        antipodal_grasps(sphere, 3, 0.3, progress="yes")


def test_progress_bar_on_stderr_only_when_asked(capsys):
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    cube = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    antipodal_grasps(sphere, 3, 0.3, GraspSampling(max_samples=20), jaws=None, seed=0, progress=True)
    horizontal_grasps(cube, [0.0], 4, 0.3, pad=None, progress=True)
    out, err = capsys.readouterr()
    assert out == ""
    assert "antipodal_grasps" in err and "/20 " in err and "kept=3" in err
    assert "horizontal_grasps" in err and "4/4 " in err
    for progress in (False, None):  # None: stderr captured here is no terminal
        antipodal_grasps(sphere, 3, 0.3, GraspSampling(max_samples=20), jaws=None, seed=0, progress=progress)
        horizontal_grasps(cube, [0.0], 4, 0.3, pad=None, progress=progress)
        assert capsys.readouterr() == ("", "")


def test_automatic_bar_on_a_terminal_only_for_long_calls(monkeypatch):
    """progress=None on a terminal: the bar waits config.RUN.progress_delay_s before it appears, so a
    call shorter than that prints nothing and a longer one shows it."""
    import io

    from workbench import config

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.03)
    for delay, shown in ((1e6, False), (0.0, True)):
        term = Terminal()
        monkeypatch.setattr(sys, "stderr", term)
        with config.override(progress_delay_s=delay):
            antipodal_grasps(sphere, 3, 0.3, GraspSampling(max_samples=20), jaws=None, seed=0)
        assert ("antipodal_grasps" in term.getvalue()) is shown, delay


def test_reach_profile_is_the_same_from_the_cached_fine_surface(monkeypatch):
    """The samplers have the whole mesh refined once (reach.fine_surface); reach_profile then
    takes the sub-triangles of the faces near the pad from it instead of refining them per
    press: the same triangles in the same order, so the same profile bit for bit."""
    from workbench.sources import reach

    monkeypatch.setattr(reach, "_FINE", {})
    mesh = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=24)  # long coarse faces
    pts, fid = trimesh.sample.sample_surface(mesh, 12, seed=5)
    rng = np.random.default_rng(5)
    approaches = -mesh.face_normals[fid] + 0.3 * rng.normal(size=(12, 3))

    def press():
        out = []
        for p, a in zip(pts, approaches, strict=True):
            try:
                prof = reach.reach_profile(mesh, p, a, press=reach.WinklerPress(closing=1e-3, max_edge=1e-3))
            except ValueError as exc:
                out.append(str(exc))
                continue
            out.append([prof.centers, prof.normals, prof.areas, prof.pressures])
        return out

    cold = press()
    assert reach._FINE == {}  # a press alone does not refine the whole mesh
    reach.fine_surface(mesh, 1e-3)
    warm = press()
    assert sum(not isinstance(c, str) for c in cold) >= 8
    for c, w in zip(cold, warm, strict=True):
        assert c == w if isinstance(c, str) else all(np.array_equal(x, y) for x, y in zip(c, w, strict=True))


def test_horizontal_grasps_refuse_a_centre_off_the_object_and_no_heights(caplog):
    """A centre in mm and an empty height list returned 0 grasps without a word (second trial)."""
    bottle = trimesh.creation.cylinder(radius=0.03, height=0.1, sections=32)
    with pytest.raises(ValueError, match="centre must be .* inside the mesh's box"):
        horizontal_grasps(bottle, [0.0], 2, mu=0.5, centre=(10.0, 0.0))
    with pytest.raises(ValueError, match="at least one height"):
        horizontal_grasps(bottle, [], 2, mu=0.5)
    with caplog.at_level(logging.WARNING, logger="workbench.grasp.sampling"):
        g = horizontal_grasps(bottle, [0.0], 2, mu=0.01, pad=None)  # a cone too narrow for any
    assert len(g) == 0 and any("0 kept" in m for m in caplog.messages)
