"""benchmarks/bench_pareto.py in quick mode: every knob family measured, fronts non-dominated,
one default each, and the FEM and twist-count points against what they must satisfy."""

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
FAMILIES = {
    "twist count K (ellipsoid_sdp)",
    "twist count K (quartic_normals)",
    "limit-surface model",
    "linearisation M",
    "FEM mesh x fidelity",
    "quadrature rtol",
}


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    sys.path.insert(0, str(BENCH))  # the script imports its sibling benchmarks
    try:
        spec = importlib.util.spec_from_file_location("bench_pareto", BENCH / "bench_pareto.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        out = tmp_path_factory.mktemp("pareto") / "pareto.json"
        mod.run(quick=True, out=out)
    finally:
        sys.path.remove(str(BENCH))
    return out, json.loads(out.read_text())


def test_every_family_is_written_with_its_figure(result):
    out, res = result
    assert set(res["families"]) == FAMILIES
    assert out.with_suffix(".png").stat().st_size > 0
    assert res["machine"]["fma_gflops_measured"] > 0


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_points_front_and_default(result, name):
    fam = result[1]["families"][name]
    pts = fam["points"]
    t = np.array([p["runtime_s"] for p in pts])
    e = np.array([p["error"] for p in pts])
    assert (t > 0).all() and (e >= 0).all() and np.isfinite(e).all()
    if fam["reference_setting"] is not None:  # a reference among the settings is exact for itself
        (ref,) = [p for p in pts if p["setting"] == fam["reference_setting"]]
        assert ref["error"] == 0.0
    # the front against brute force: a point is on it iff no other point is at least as good in both
    # and better in one (exact duplicates would keep the first; the settings here differ)
    brute = [
        not any(
            t[j] <= t[i] and e[j] <= e[i] and (t[j] < t[i] or e[j] < e[i]) for j in range(len(pts)) if j != i
        )
        for i in range(len(pts))
    ]
    assert [p["on_front"] for p in pts] == brute
    assert fam["front"] == [pts[i]["setting"] for i in np.argsort(t) if brute[i]]
    defaults = [p for p in pts if p["is_default"]]
    assert len(defaults) == 1
    d = defaults[0]
    assert fam["default"] == d["setting"] and fam["default_on_front"] == d["on_front"]
    assert fam["default_error"] == d["error"] and fam["default_runtime_s"] == d["runtime_s"]
    # the cheapest setting within a budget: no point meeting the budget is faster
    for budget, setting in fam["cheapest_within"].items():
        within = [p for p in pts if p["error"] <= float(budget)]
        if setting is None:
            assert not within
        else:
            best = next(p for p in pts if p["setting"] == setting)
            assert best["error"] <= float(budget)
            assert best["runtime_s"] == min(p["runtime_s"] for p in within)


def test_condensed_and_full_mesh_linear_solve_one_problem(result):
    # the condensed face compliance is the full mesh's linear problem, reduced exactly
    pts = result[1]["families"]["FEM mesh x fidelity"]["points"]
    by = {(p["fidelity"], tuple(p["mesh"])): p["force_N"] for p in pts}
    meshes = {m for f, m in by if f == "condensed"}
    assert meshes and meshes == {m for f, m in by if f == "linear"}
    for m in meshes:
        assert by[("condensed", m)] == pytest.approx(by[("linear", m)], rel=1e-6)
    # and the neo-Hookean layer stiffens at 20 % compression: more force than the linear one
    for m in meshes:
        assert by[("nonlinear", m)] > by[("linear", m)]


def test_more_twists_fit_the_quartic_better(result):
    # Eq. 3.18 on held-out wrenches falls from the fewest to the most training wrenches
    pts = result[1]["families"]["twist count K (quartic_normals)"]["points"]
    by_k = sorted(pts, key=lambda p: p["K"])
    assert by_k[-1]["error"] < by_k[0]["error"]
    # and the outer/inner linearisation gap shrinks with M
    m_pts = sorted(result[1]["families"]["linearisation M"]["points"], key=lambda p: p["M"])
    assert all(a["error"] > b["error"] > 0 for a, b in zip(m_pts, m_pts[1:], strict=False))
