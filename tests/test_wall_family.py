"""Bottle-family walls (workbench.fem.wall_family): the grasp axis at the section's major axis
plus the angle, one cached wall per (bottle, mesh), mesh convergence relative to the finest, a
bottle's map from its rows, and the convergence benchmark's file read back."""

from __future__ import annotations

import json

import numpy as np
import pytest

from workbench.fem.bottle import Bottle, bottle_family
from workbench.fem.material import Material
from workbench.fem.wall_family import bottle_wall, grasp_axis, mesh_convergence, mesh_error, stiffness_map


def test_the_grasp_axis_turns_from_the_sections_major_axis():
    b = Bottle(bottle_family(seed=0)[16])  # an asymmetric bottle: its major axis turns with height
    z = 0.4 * b.params.height
    centre, A, B, phi = b.section(z)
    for angle in (0.0, 0.3, np.pi / 2):
        p, e = grasp_axis(b, z, angle)
        assert p == pytest.approx([centre[0], centre[1], z], abs=1e-15)
        assert np.linalg.norm(e) == pytest.approx(1.0, rel=1e-15) and e[2] == 0.0
        assert np.arctan2(e[1], e[0]) == pytest.approx(np.arctan2(np.sin(phi + angle), np.cos(phi + angle)))


@pytest.mark.jit_only("a wall's assembly and factorisation: over 10 s as pure Python")
def test_a_bottles_wall_is_built_once_and_the_finest_mesh_is_the_reference():
    bottle_wall.cache_clear()
    b1, w1 = bottle_wall(0, 0, 2.5e9, 0.4, 0.5e-3, 16, 8)
    b2, w2 = bottle_wall(0, 0, 2.5e9, 0.4, 0.5e-3, 16, 8)
    assert w1 is w2 and b1 is b2 and bottle_wall.cache_info().hits == 1
    assert b1.params.height == Bottle(bottle_family(seed=0)[0]).params.height
    conv = mesh_convergence(b1, Material(2.5e9, 0.4), 0.5e-3, [[16, 8], [24, 12]], 10.0, (0.02, 0.04))
    assert [(r["mesh"], r["angle"]) for r in conv] == [
        ("16x8", 0.0),
        ("16x8", np.pi / 2),
        ("24x12", 0.0),
        ("24x12", np.pi / 2),
    ]
    assert conv[2]["rel_to_finest"] == 0.0 and conv[3]["rel_to_finest"] == 0.0
    for coarse, fine in ((conv[0], conv[2]), (conv[1], conv[3])):
        k, k_ref = coarse["stiffness_N_per_m"], fine["stiffness_N_per_m"]
        assert coarse["rel_to_finest"] == pytest.approx(k / k_ref - 1, rel=1e-12)
        # conforming displacement elements are too stiff: the coarser wall the stiffer
        assert 0 < k_ref < k < 1e6
    bottle_wall.cache_clear()


def test_a_bottles_map_from_its_rows_in_any_order():
    """Heights x angles from rows in any order (another bottle's left out), an angle recomputed
    to its last bit found, an implausible grasp (None) counted and left out of min and max."""
    angles = np.array([0.0, np.pi / 2])
    rows = [
        {"bottle": 3, "height_fraction": 0.5, "angle": np.pi / 2 + 1e-13, "stiffness_N_per_m": 500.0},
        {"bottle": 5, "height_fraction": 0.2, "angle": 0.0, "stiffness_N_per_m": 1.0},
        {"bottle": 3, "height_fraction": 0.2, "angle": np.pi / 2, "stiffness_N_per_m": 2000.0},
        {"bottle": 3, "height_fraction": 0.5, "angle": 0.0, "stiffness_N_per_m": None},
        {"bottle": 3, "height_fraction": 0.2, "angle": 0.0, "stiffness_N_per_m": 1000.0},
    ]
    m = stiffness_map(rows, 3, [0.2, 0.5], angles, asymmetric=True)
    assert m == {
        "asymmetric": True,
        "height_fractions": [0.2, 0.5],
        "angles_rad": [0.0, np.pi / 2],
        "stiffness_N_per_m": [[1000.0, 2000.0], [None, 500.0]],
        "n_implausible": 1,
        "min": 500.0,
        "max": 2000.0,
    }
    none = stiffness_map(rows[3:4], 3, [0.5], angles[:1], asymmetric=False)
    assert none["n_implausible"] == 1 and none["min"] is None and none["max"] is None


def test_mesh_error_reads_the_convergence_benchmark(tmp_path):
    """Per region the number of grasps and the min, median and max of the mesh's error relative
    to the finest mesh, by hand; a mesh not measured and a missing or broken file say so."""

    def loc(region, **rel):
        return {"region": region, "finest": "120x60", "rel_to_finest": rel}

    path = tmp_path / "shoulder_convergence.json"
    data = {
        "locations": [
            loc("body", **{"24x12": 0.30, "48x24": 0.10}),
            loc("body", **{"24x12": 0.20, "48x24": 0.04}),
            loc("body", **{"48x24": 0.07}),
            loc("below_shoulder", **{"48x24": -0.01, "24x12": 0.5}),
            loc("below_shoulder", **{"48x24": 0.21}),
        ]
    }
    path.write_text(json.dumps(data))
    e = mesh_error([48, 24], path)
    assert e["measured"] and e["reference_mesh"] == "120x60"
    assert e["rel_to_reference"] == {
        "body": {"n": 3, "min": 0.04, "median": 0.07, "max": 0.10},
        "below_shoulder": {"n": 2, "min": -0.01, "median": pytest.approx(0.10, rel=1e-12), "max": 0.21},
    }
    text = "body +4%..+10% (median +7%, 3 grasps); below shoulder -1%..+21% (median +10%, 2 grasps)"
    assert f"mesh [48, 24] vs 120x60 on the benchmark's bottles: {text}; a jaw edge" in e["note"]
    e = mesh_error((24, 12), path)
    assert e["rel_to_reference"]["body"] == {"n": 2, "min": 0.20, "median": 0.25, "max": 0.30}
    assert e["rel_to_reference"]["below_shoulder"] == {"n": 1, "min": 0.5, "median": 0.5, "max": 0.5}
    e = mesh_error([16, 8], path)
    assert not e["measured"] and "mesh [16, 8] not measured (measured: ['24x12', '48x24']" in e["note"]
    for absent in (tmp_path / "none.json", tmp_path):
        assert mesh_error([48, 24], absent) == {
            "measured": False,
            "note": f"no convergence measurement at {absent} (make bench-shoulder writes it)",
        }
    (tmp_path / "broken.json").write_text("{not json")
    assert not mesh_error([48, 24], tmp_path / "broken.json")["measured"]
