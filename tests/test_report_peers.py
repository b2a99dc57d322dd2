"""workbench.runner.report_peers: the peers and Pareto sections of REPORT.md from summaries only."""

import json

from workbench.runner.report import Summaries, write_report
from workbench.runner.report_peers import render_peers_sections


def _write(root, rel, data):
    path = root / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data))


PEERS = {
    "config": {
        "pad_mm": [16.0, 20.0, 5.0],
        "E": 1.0e6,
        "nu": 0.45,
        "mu": 0.5,
        "deltas_mm": [0.25, 1.0],
        "ls_model": "ellipsoid_sdp",
        "ls_twists": 500,
        "ls_directions": 2000,
    },
    "peers": {
        "drake": {
            "sphere": {
                "force_rel_err": -0.4731,
                "area_rel_err": 0.02,
                "pressure_rel_l2": 0.4,
                "torsion_rel_err": -0.1,
                "margin_rel_err": 0.0609,
                "ls_rel_err": 0.0312,
                "ls_bias": -0.021,
                "ms_per_query": 3.25,
            }
        },
        "foundation": {
            "sphere": {
                "force_rel_err": -0.55,
                "area_rel_err": 0.2,
                "pressure_rel_l2": 0.5,
                "torsion_rel_err": -0.04,
                "margin_rel_err": 0.0,
                "ms_per_query": 5.6,
            }
        },
        "mujoco_hertz": {
            "sphere": {
                "force_rel_err": None,
                "area_rel_err": None,
                "pressure_rel_l2": None,
                "torsion_rel_err": -0.33,
                "margin_rel_err": 0.27,
                "ms_per_query": 0.1,
            }
        },
    },
    "vs_drake": {
        "sphere": {
            "force_rel_err": {
                "drake_ms": 3.25,
                "drake_error": 0.47,
                "condensed_error_at_drake_ms": 0.16,
                "error_ratio_drake_over_condensed": 2.9,
                "error_ratio_clamped": True,
                "error_ratio_bound": ">=",
                "condensed_ms_at_drake_error": 20.0,
                "runtime_ratio_drake_over_condensed": 0.16,
                "runtime_ratio_clamped": True,
                "runtime_ratio_bound": "<=",
            }
        }
    },
    "margin_resolution": 0.00816,
    "mapping": {"drake": "E_hydro = E"},
    "hertz_half_space": {
        "delta_mm": 0.1125,
        "force_rel_err": [0.0727, 0.0376],
        "a_over_H": [0.075, 0.0375],
        "extrapolated_force_rel_err": 0.0025,
    },
    "peer_versions": {"drake": "1.51.1"},
    "figures": ["/somewhere/results/peers/runtime_vs_error.png"],
}
PARETO = {
    "families": {
        "twist count K": {
            "reference": "K = 2000",
            "default_error": 0.0123,
            "default_runtime_s": 0.5,
            "default_on_front": True,
            "cheapest_within": {"0.1": "K=50", "0.001": None},
            "points": [{"setting": "K=600", "is_default": True}, {"setting": "K=50", "is_default": False}],
        }
    },
    "figure": "results/benchmarks/pareto.png",
}


def test_sections_render_the_summaries_numbers(tmp_path):
    _write(tmp_path, "peers/summary.json", PEERS)
    _write(tmp_path, "benchmarks/pareto.json", PARETO)
    text = render_peers_sections(Summaries(tmp_path), "../results/")
    row = next(line for line in text.splitlines() if line.startswith("| Drake hydroelastic | sphere"))
    assert (
        "-47.3 %" in row and "| 40.0 % |" in row and "| 6.1 % |" in row and "| -2.1 % | 3.1 % | 3.25 |" in row
    )
    mj = next(line for line in text.splitlines() if line.startswith("| MuJoCo cone, torsion 3πμa/16"))
    # no force, area, pressure, torque (no force), bias nor fitted 6DLS from a point contact
    assert mj.count("—") == 7 and "-33.0 %" in mj and "| 27.0 % |" in mj
    assert (
        "16.0 × 20.0 × 5.0 mm, E = 1 MPa, ν = 0.45, μ = 0.5; jaw displacements δ = 0.25, 1.0 mm; "
        "the fitted 6DLS: ellipsoid_sdp on 1000 wrenches, scored at 2000 points" in text
    )
    assert "+7.3 % at a/H = 0.075, +3.8 % at a/H = 0.0375" in text and "is +0.2 % from it" in text
    f = next(line for line in text.splitlines() if line.startswith("| elastic foundation"))
    assert "| < 0.8 % |" in f  # below the margins' bisection resolution: unresolved, not zero
    assert "| >=2.9 |" in text and "| <=0.16 |" in text  # the side each bound lies on
    assert "[peers/runtime_vs_error.png](../results/peers/runtime_vs_error.png)" in text
    k = next(line for line in text.splitlines() if line.startswith("| twist count K"))
    assert "K=600" in k and "0.0123" in k and "0.1: K=50; 0.001: none" in k
    assert "[benchmarks/pareto.png](../results/benchmarks/pareto.png)" in text


def test_missing_summaries_say_which_and_how_to_make_them(tmp_path):
    text = render_peers_sections(Summaries(tmp_path))
    assert "missing: peers/summary.json:peers — run `workbench run peers`" in text
    assert "missing: benchmarks/pareto.json:families — run `python benchmarks/bench_pareto.py`" in text


def test_the_report_file_carries_the_sections(tmp_path):
    _write(tmp_path, "peers/summary.json", PEERS)
    path = write_report(tmp_path)
    text = path.read_text()
    assert "## Against the peers" in text and "## Our knobs: runtime against error" in text


def test_every_table_row_has_its_header_s_cells(tmp_path):
    """A '|' inside a cell splits it: every row of each rendered table has as many cells as
    its header (the first rendering named a column 'margin |error|')."""
    _write(tmp_path, "peers/summary.json", PEERS)
    _write(tmp_path, "benchmarks/pareto.json", PARETO)
    text = render_peers_sections(Summaries(tmp_path))
    header = None
    for line in text.splitlines():
        if not line.startswith("|"):
            header = None
            continue
        cells = line.count("|")
        if header is None:
            header = cells
        assert cells == header, line
