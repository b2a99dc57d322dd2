"""Each experiment in quick mode (scikit-fem ``test_examples`` style): the
headline numbers against the thesis, and the summary.json key contract."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from workbench.runner.cli import main
from workbench.runner.experiment_config import build_config

#: the thesis's 24 meshes (CC BY-NC 4.0: read by path beside the repository, never copied into it)
THESIS_OBJECTS = Path(__file__).resolve().parents[2] / "shared" / "data" / "thesis_objects"

SURFACES = [f"S{i}" for i in range(1, 7)]
# Left out of `make test-nojit`: as pure Python one quick run takes minutes (docs/decisions.md).
_JIT_ONLY = pytest.mark.jit_only(
    "a whole experiment in quick mode: minutes as pure Python; every kernel it calls also runs "
    "without JIT in the unit tests (make test-nojit checks with --check-kernels)"
)


def EXPERIMENT_RUN(test):  # noqa: N802 - used as a marker
    """A whole experiment in quick mode: slow (collected first) and left out of make test-nojit."""
    return pytest.mark.slow(_JIT_ONLY(test))


@pytest.fixture(scope="module")
def parametric(tmp_path_factory):
    out = tmp_path_factory.mktemp("ps")
    assert main(["run", "parametric-surfaces", "--quick", "--out", str(out), "--seed", "3"]) == 0
    return out, json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def discretization(tmp_path_factory):
    out = tmp_path_factory.mktemp("disc")
    assert main(["run", "discretization", "--quick", "--out", str(out)]) == 0
    return out, json.loads((out / "summary.json").read_text())


@EXPERIMENT_RUN
def test_parametric_surfaces_example_3_2_5(parametric):
    _, s = parametric
    ex = s["example_3_2_5"]
    np.testing.assert_allclose(ex["pressure_center"], [0, 0.018, -0.04], atol=5e-5)
    assert round(ex["F"], 4) == 0.6283
    np.testing.assert_allclose(ex["normal_wrench"], [0, -0.5657, 0, 0, 0, 0], atol=5e-5)
    np.testing.assert_allclose(ex["frictional_wrench"], [0, 0, 0, 0, 0.0018, 0], atol=5e-5)


@EXPERIMENT_RUN
def test_parametric_surfaces_table_3_2(parametric):
    _, s = parametric
    for model, thesis in s["table_3_2_thesis"].items():
        assert np.abs(np.array(s["table_3_2"][model]) - thesis).max() <= 0.01, model
    assert set(s["table_3_2"]) == {"6d_nonplanar", "3d_nonplanar", "planar"}
    assert all(len(v) == 6 for v in s["table_3_2"].values())


@EXPERIMENT_RUN
def test_parametric_surfaces_w_max_and_pca(parametric):
    out, s = parametric
    assert set(s["w_max_exact"]) == set(SURFACES) and all(len(v) == 6 for v in s["w_max_exact"].values())
    # sampled maxima never exceed the exact support values
    for name in SURFACES:
        assert (np.array(s["w_max_sampled"][name]) <= np.array(s["w_max_exact"][name]) * (1 + 1e-4)).all()
    # thesis §3.5.1.1: five or six significant components on every surface
    assert set(s["pca_components"]) == set(SURFACES)
    assert all(v in (5, 6) for v in s["pca_components"].values())
    assert s["seed"] == 3 and "numba" in s["versions"]
    for fig in s["figures"]:
        assert (out / fig.split("/")[-1]).stat().st_size > 10_000
    assert (out / "table_3_2.csv").read_text().count("\n") == 1 + 6 * 3


@EXPERIMENT_RUN
def test_discretization_fig_3_8(discretization):
    out, s = discretization
    assert set(s["error_rate"]) == set(SURFACES)
    for name in SURFACES:
        rates = s["error_rate"][name]
        assert rates["300"] < 0.04 and rates["1000"] < 0.01, (name, rates)
        assert rates["25"] > rates["300"] > rates["1000"]  # converges with refinement
    # runtimes are reported, not asserted against each other: timings depend on the
    # machine's load (on a busy machine the ordering can flip)
    assert s["runtime_discrete_s"] > 0 and s["runtime_continuous_s"] > 0
    assert (out / "error_rate.csv").exists() and (out / "fig_3_8_error_rate.png").exists()


@pytest.mark.parametrize(
    "name, sets, match",
    [
        # the keys' allowed words (experiments' KEYS: the library's own lists), before check_config
        ("fem-fitting", {"fine_level": 9}, r"--set fine_level=9: fine_level must be one of \[-1, 0, 1"),
        ("ls-fitting", {"support_directions": 0}, "support_directions must be a positive"),
        ("fem-fitting", {"downsample_steps": 0.0}, "downsample_steps must be >= 2"),
        (
            "fem-fitting",
            {"code_frame": "pad"},
            r"--set code_frame=\"pad\": code_frame must be one of \['object', 'jaw'\]; got 'pad'",
        ),
        ("fem-fitting", {"ablation_cell_mm": 0.003}, "ablation_cell_mm must be a cell size in mm"),
        (
            "sensitivity",
            {"training_samplers": ["thesis", "nope"]},
            r".*: training_samplers must be one of \['thesis', '6dfc'",
        ),
        # a sweep trial's values that failed only inside the run (the same rules, called early)
        ("sensitivity", {"n_elements": 0}, "n_elements must be >= 2"),
        ("sensitivity-engine", {"seeds": []}, "seeds must be distinct integers"),
        ("sensitivity-engine", {"seeds": [0, 0]}, "seeds must be distinct integers"),
        ("sensitivity-engine", {"pad_E": 1.0}, r"--set pad_E=1.0: .*probably in MPa"),
        ("sensitivity-engine", {"half_angle": 34.0}, r"--set half_angle=34.0: .*probably in degrees"),
        ("sensitivity", {"n_elements": 1}, "n_elements must be >= 2"),
        (
            "sensitivity",
            {"models": ["6dls", "bogus"]},
            r".*: models must be one of \['point', .* got \['6dls', 'bogus'\]",
        ),
        ("sensitivity", {"training_models": ["nope"]}, r".*: training_models must be one of \['point'"),
        ("sensitivity", {"models": []}, "models must name at least one model"),
        ("sensitivity", {"mu": 0.0}, "mu = 0 is a frictionless grasp: the simulated truth resists none"),
        ("sensitivity", {"robust_disturbances": 41}, r"n_disturbances .* robust_disturbances in \[1, n_"),
        ("sensitivity", {"n_disturbances": 0}, "n_disturbances must be >= 1"),
        ("sensitivity", {"precision_levels": [90.0]}, r"levels must be precision levels in \(0, 1\]"),
        # the peers' careless inputs of a new-user trial: each ran to nonsense or failed late
        ("peers", {"margin_steps": 0}, "margin_steps must be an integer >= 1"),
        (
            "peers",
            {"E": 1.0},
            r"--set E=1.0: E \[Pa\] must be a pad Young's modulus .* probably in MPa — pass 1e\+06",
        ),
        ("peers", {"hertz_block": {"R_mm": 20}}, "hertz_block must be a dict of exactly"),
        ("peers", {"ls_twists": 0}, "ls_twists must be an integer >= 1"),
        (
            "peers",
            {"pad_mm": [0.016, 0.02, 0.005]},
            r".*: pad_mm\[0\] \[mm\] must be a pad size .* probably in metres — pass 16 \[mm\]",
        ),
        ("peers", {"condensed_sweep_cells": []}, "condensed_sweep_cells must list at least one"),
        ("peers", {"ls_twists": 5}, "ls_twists must be an integer >= 11"),
        (
            "peers",
            {
                "hertz_block": {
                    "R_mm": 20.0,
                    "a_mm": 1.5,
                    "nu": 0.3,
                    "fine_mm": 0.45,
                    "depths_mm": [20.0, 30.0],
                }
            },
            "hertz_block must have depths_mm",
        ),
    ],
)
def test_settings_a_default_cannot_judge_are_refused_before_any_work(name, sets, match):
    with pytest.raises(SystemExit, match=f"{name}: {match}"):
        build_config(name, True, None, None, sets)


@pytest.fixture(scope="module")
def ls_fitting(tmp_path_factory):
    out = tmp_path_factory.mktemp("ls")
    sets = ["--set", 'surfaces=["S1","S3","S5"]', "--set", "section_surface=S3"]
    assert main(["run", "ls-fitting", "--quick", "--out", str(out), *sets]) == 0
    return out, json.loads((out / "summary.json").read_text())


@EXPERIMENT_RUN
def test_ls_fitting_headlines(ls_fitting):
    out, s = ls_fitting
    surfaces = ["S1", "S3", "S5"]
    assert set(s["heldout_error"]) == {"ellipsoid_lsq", "ellipsoid_sdp", "quartic_values", "quartic_normals"}
    for model in ("ellipsoid_sdp", "quartic_normals"):
        assert set(s["heldout_error"][model]) == set(surfaces)
    for name in surfaces:
        e, q = (
            s["heldout_error"]["ellipsoid_sdp"][name]["600"],
            s["heldout_error"]["quartic_normals"][name]["600"],
        )
        assert q < e, name  # thesis §3.5.1.3: the quartic wins with enough wrenches
        # thesis-code protocol (the author's own code's twist grid): the author's wrench set is
        # harder to fit than the thesis-text sampler's held-out set — the cause of our 2x gap to
        # the thesis's numbers
        tc = s["thesis_protocol_error"]
        assert tc["ellipsoid_sdp"][name]["600"] > 1.3 * e and tc["quartic_normals"][name]["600"] > 1.3 * q, (
            name
        )
        down = tc["downsampled"][name]
        assert 122 <= down["n_train"] <= 294, down  # the author's code trains on 122-294 wrenches
        assert tc["n_pool"][name] == 48_483
        assert down["quartic_normals"] < down["ellipsoid_sdp"], name
        # sampler-independent error: the quartic's surface is closer to the exact one
        for proto in ("thesis-text", "thesis-code", "thesis-code-downsampled"):
            sup = s["support_error"][proto]
            assert sup["quartic_normals"][name]["radial_mean"] < sup["ellipsoid_sdp"][name]["radial_mean"], (
                proto
            )
        # K = 200 (126 coefficients): the values-only quartic of Eq. 3.17 overfits; the twist
        # normals (maximum dissipation) fix it — quartic below the ellipsoid from K = 200 on
        e2, q2 = (
            s["heldout_error"]["ellipsoid_sdp"][name]["200"],
            s["heldout_error"]["quartic_normals"][name]["200"],
        )
        assert q2 < e2, (name, q2, e2)
        assert q2 < s["heldout_error"]["quartic_values"][name]["200"], name
    # Eq. 3.12's log-det penalty: inert at the former α = 1e-6·K, harmful at 1e-2·K
    change = s["sdp_log_det_effect"]["max_change_vs_alpha_0"]
    assert change["1e-06"] < 1e-4 < 1e-3 < change["0.01"]
    assert s["fig_3_9_vs_thesis"]["thesis-code"]["quartic_normals"]["thesis_as_low_as"] == 0.02
    rt = s["fit_runtime_s"]
    assert set(rt) == {"ellipsoid_lsq", "ellipsoid_sdp", "quartic_values", "quartic_normals"}
    assert all(rt["ellipsoid_lsq"][n]["600"] < rt["quartic_normals"][n]["600"] for n in surfaces)
    # the solver that answered: SCS for the quartic with normals; the SDP ellipsoid's definite
    # least squares on S1-S6 is returned without a conic solve
    by_model = {(r["model"], r["solver"]) for r in s["solver_comparison"]}
    assert by_model == {
        ("quartic_normals", "SCS"),
        ("ellipsoid_sdp", "numpy.linalg.lstsq"),
    }
    for fig in ("fig_3_9_error_runtime.png", "runtime_vs_error.png", "fig_3_10_cross_sections.png"):
        assert (out / fig).stat().st_size > 10_000


@EXPERIMENT_RUN
def test_fem_validation_quick(tmp_path):
    assert main(["run", "fem-validation", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    worst = s["locking"][-1]
    assert worst["nu"] >= 0.499 and abs(worst["sri_over_exact"] - 1) < 0.02 and worst["full_over_exact"] < 0.8
    assert all(abs(w["rel_err"]) < 0.05 for w in s["thin_layer"])  # within 5% where the limit applies
    # incompressible thin film (plane strain): the (h/a)² correction shrinks with a/h,
    # within 5% of P' = 2Ga⁵/(15Rh³) at a/h = 20
    film = {w["a_over_h"]: w["rel_err"] for w in s["thin_film"]}
    assert abs(film[20]) < 0.05 < abs(film[10])
    assert len(s["condensed_vs_full_cases"]) >= 10
    assert s["condensed_vs_reference"]["pressure_rel_l2"] <= 0.02
    assert s["condensed_vs_reference"]["force_rel_err"] <= 0.01
    assert all(r["min_pressure"] >= 0 for r in s["condensed_vs_full_cases"])
    assert s["force_displacement"]["monotone"]
    # Hertz on the coarsest mesh only (h = a/2.5): O(h/a) errors; the 3% bar is for the
    # finest mesh of the full run (results/fem-validation/hertz_convergence.csv)
    hz = s["hertz"]["convergence"][0]
    assert abs(hz["a_rel_err"]) < 0.1 and abs(hz["p0_rel_err"]) < 0.03
    assert hz["patch_edge_force_N"] == 0.0  # the condensed patch contains the contact
    # linear vs neo-Hookean rows: at δ/h = 2% the same discretization agrees (small-strain
    # limit), the neo-Hookean force grows with δ and linear theory falls behind it
    rows = s["fidelity"]["rows"]
    for case in ("cylinder R15", "sphere R15"):
        mine = [r for r in rows if r["case"] == case]
        assert sorted({round(r["delta_over_h"], 2) for r in mine}) == [0.02, 0.2, 0.4, 0.6]
        small = next(r for r in mine if r["level"] == "condensed full" and r["delta_over_h"] < 0.05)
        assert abs(small["force_rel_err"]) < 0.02 and small["pressure_rel_l2"] < 0.02
        nl = [r["nl_force_N"] for r in mine if r["level"].startswith("nonlinear")]
        assert all(np.diff(nl) > 0)
        deep = next(r for r in mine if r["level"] == "condensed full" and r["delta_over_h"] > 0.5)
        assert deep["force_rel_err"] < -0.2


@EXPERIMENT_RUN
def test_power_law_quick(tmp_path):
    """Fig 4.2(d) in quick mode: two cylinders × three displacements, each fit in the CSV and the
    summary alike, the force growing with the displacement, k inside the search interval."""
    assert main(["run", "power-law", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    cases = s["cases"]
    assert [(c["b_m"], c["delta_mm"]) for c in cases] == [
        (b, d) for b in (0.02, 0.04) for d in (1.0, 2.0, 3.0)
    ]
    with open(tmp_path / "power_law.csv") as fh:
        table = list(csv.DictReader(fh))
    assert [float(r["k"]) for r in table] == pytest.approx([c["k"] for c in cases], rel=1e-12)
    for b in (0.02, 0.04):
        forces = [c["force_N"] for c in cases if c["b_m"] == b]
        assert np.all(np.diff(forces) > 0)  # pressed further, pushed harder
        widths = [c["r_max_m"] for c in cases if c["b_m"] == b]
        assert np.all(np.diff(widths) > 0)  # and a wider contact
    ks = [c["k"] for c in cases]
    assert s["n_k_at_bound"] == 0 and s["k_range"] == [min(ks), max(ks)]
    assert all(0.5 < k < 1000 for k in ks) and 0 < s["max_rms_rel"] < 1
    assert (tmp_path / "fig_4_2d_power_law.png").is_file()


def _check_set_tables(ran: dict, rows_of: list[dict]) -> None:
    """fem-fitting quick: each object set's Table 3.3 against its own rows."""
    # the quartic below the ellipsoid on average (Table 3.3) under both protocols, on each set,
    # wherever it was fitted: under the thesis code's training grid only on a profile with at
    # least its 126 unknowns of training wrenches (none on mesh 0006: 96-118)
    for name, v in ran.items():
        tab = v["table_3_3_vs_thesis"]
        n_train = [r["code_n_train"] for r in rows_of if r["object_set"] == name]
        fitted = sum(n >= 126 for n in n_train)
        assert tab["thesis-code"]["quartic_values"]["n_profiles"] == fitted, name
        assert v["thesis_protocol_error"]["quartic_underdetermined"] == len(n_train) - fitted, name
        assert (tab["thesis-code"]["quartic_values"]["mean"] is None) == (fitted == 0), name
        for proto in ("thesis-text", "thesis-code"):
            q, e = tab[proto]["quartic_values"]["mean"], tab[proto]["ellipsoid_sdp"]["mean"]
            assert q is None or q < e, (name, proto)
        for m in ("ellipsoid_sdp", "quartic_values"):
            if tab["thesis-code"][m]["mean"] is None:
                continue
            assert tab["thesis-code"][m]["mean"] > 2 * tab["thesis-text"][m]["mean"], (name, m)
            # trained on the author's wrench set, the surface is closer to the exact one wherever
            # it is measured (uniform normals), not only on that set
            sup = v["support_error"]
            assert sup["thesis-code"][m]["mean"] < sup["thesis-text"][m]["mean"], (name, m)
        # the author reports 122-294 training wrenches on their contacts; ours in the object
        # frame are of that order (quick run: about 95-160; full run in the README)
        assert 90 <= min(n_train) and max(n_train) <= 294, name


@EXPERIMENT_RUN
def test_fem_fitting_quick(tmp_path):
    """Table 3.3 pipeline in quick mode: the thesis's mesh 0006 (when the data is beside the
    repository) and two family bottles -> profiles -> both fits, each set's table side by side."""
    assert main(["run", "fem-fitting", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    sets = s["object_sets"]
    ran = {k: v for k, v in sets.items() if "skipped" not in v}
    meshes = THESIS_OBJECTS.is_dir()
    assert list(sets) == ["thesis_meshes", "bottle_family"]
    assert s["headline_object_set"] == ("thesis_meshes" if meshes else "bottle_family")
    if meshes:  # one mesh x one height x two approaches x three displacements
        assert sets["thesis_meshes"]["n_objects"] == 1 and sets["thesis_meshes"]["n_profiles"] == 6
    else:
        assert "skipped" in sets["thesis_meshes"]
    assert sets["bottle_family"]["n_objects"] == 2 and sets["bottle_family"]["n_profiles"] == 12
    # the headline set's table is the top level's
    assert s["table_3_3_vs_thesis"] == ran[s["headline_object_set"]]["table_3_3_vs_thesis"]
    # every task (a profile each, plus the full-mesh reference cases) is in the task stats
    n_profiles = sum(v["n_profiles"] + v["n_empty"] for v in ran.values())
    stream = s["tasks_stream"]
    n_tasks = sum(w["tasks"] for w in stream["workers"].values())
    assert n_tasks == n_profiles + len(s["condensed_vs_reference"]["cases"])
    assert 0 < stream["busy_s"] and 0 < stream["utilisation"] <= 1 + 1e-9
    for key in (
        "n_profiles",
        "ellipsoid_sdp_error_mean",
        "ellipsoid_sdp_error_std",
        "quartic_values_error_mean",
        "quartic_values_error_std",
        "condensed_vs_reference",
        "seconds_per_profile",
    ):
        assert key in s
    assert all(v["n_empty"] == 0 for v in ran.values())
    rows_of = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    _check_set_tables(ran, rows_of)
    # the protocol ablation ran on the first profile of the headline set, every variant, and
    # each ratio is that variant's error over the protocol's own on the same profile
    abl = s["protocol_ablation"]
    first = next(r for r in rows_of if r["object_set"] == s["headline_object_set"])
    assert abl["n_profiles"] == 1
    for variant in ("jaw_frame", "origin_in_box", "coarse_elements", "author_objective"):
        cell = abl[variant]["ellipsoid_sdp"]
        assert cell["protocol_mean"] == first["ellipsoid_sdp_code_error"], variant
        assert cell["mean"] == first[f"abl_{variant}_ellipsoid_sdp"], variant
        assert np.isclose(cell["ratio"], cell["mean"] / cell["protocol_mean"], rtol=1e-12), variant
    assert s["condensed_vs_reference"]["pressure_rel_l2"] <= 0.02
    assert s["condensed_vs_reference"]["force_rel_err"] <= 0.01
    # reference_cases bottles and the elliptic cylinder, run as tasks beside the rows
    cases = [c["case"] for c in s["condensed_vs_reference"]["cases"]]
    assert len(cases) == 2 and cases[1].startswith("elliptic cylinder")
    rows = (tmp_path / "rows.jsonl").read_text().splitlines()
    assert len(rows) == n_profiles
    # a second run resumes from the checkpoint: no new rows, same table
    assert main(["run", "fem-fitting", "--quick", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "rows.jsonl").read_text().splitlines() == rows
    again = json.loads((tmp_path / "summary.json").read_text())
    assert again["quartic_values_error_mean"] == s["quartic_values_error_mean"]
    assert s["n_resumed"] == 0 and again["n_resumed"] == n_profiles


@EXPERIMENT_RUN
@pytest.mark.skipif(not THESIS_OBJECTS.is_dir(), reason="thesis objects not available")
def test_fem_fitting_records_a_press_the_pad_cannot_take_and_goes_on(tmp_path):
    """Mesh 0008 is 50 mm tall: at a quarter of its height the 40 mm pad reaches below its base,
    and a 2 mm press puts the object deeper into the pad than its 5 mm layer.  Those presses are
    rows that say why, left out of the table; the 1 mm ones are fitted."""
    sets = {"objects_glob": "0008*.obj", "heights": [0.25], "object_sets": ["thesis_meshes"]}
    argv = ["run", "fem-fitting", "--quick", "--out", str(tmp_path)]
    argv += [a for k, v in sets.items() for a in ("--set", f"{k}={json.dumps(v)}")]
    assert main(argv) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    rows = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    unsolved = [r for r in rows if "unsolved" in r]
    assert sorted((r["approach"], r["delta_mm"]) for r in unsolved) == [
        ("major", 2.0),
        ("major", 3.0),
        ("minor", 2.0),
        ("minor", 3.0),
    ]
    assert all("deeper than the layer (h = 0.005 m)" in r["unsolved"] for r in unsolved)
    assert s["n_unsolved"] == 4 and s["n_profiles"] == 2 and len(s["unsolved"]) == 2
    assert any(line.startswith("4 presses unsolved") for line in s["headline"])


def test_fem_fitting_without_the_meshes_runs_the_family_at_the_thesis_heights(tmp_path):
    """The meshes' folder absent: that set is skipped (named, not an error) and the family takes
    ``heights``, the thesis's scale; an unknown set is refused before any work."""
    from workbench.experiments import fem_fitting

    cfg = build_config("fem-fitting", False, str(tmp_path), None, {"objects_dir": str(tmp_path / "none")})
    assert fem_fitting.OBJECT_SETS == ("thesis_meshes", "bottle_family")
    with pytest.raises(SystemExit, match="object_sets must be distinct names"):
        build_config("fem-fitting", True, None, None, {"object_sets": ["thesis_meshes", "bowls"]})
    # the plan of a run without meshes: 24 bottles at the 21 thesis heights, 2 approaches
    from workbench.experiments.fem_fitting import run_plan

    plan = run_plan(cfg)
    assert plan["skipped"] == {"thesis_meshes": f"no *.obj in {tmp_path / 'none'}"}
    assert plan["n_objects"] == {"bottle_family": 24}
    assert plan["n_profiles"] == 24 * 21 * 2 * 3 == 3024


@EXPERIMENT_RUN
def test_wall_stiffness_quick(tmp_path):
    assert main(["run", "wall-stiffness", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    ring = s["ring_validation"]
    # Roark's thin ring: both diameters within 0.5% at 64 elements, converging
    assert abs(ring[-1]["perpendicular_rel_err"]) < 0.005 and abs(ring[-1]["load_line_rel_err"]) < 0.005
    assert abs(ring[0]["load_line_rel_err"]) > abs(ring[-1]["load_line_rel_err"])
    (grid,) = (np.array(m["stiffness_N_per_m"]) for m in s["maps"].values())  # heights x angles
    assert (grid > 0).all()
    # clamped base, open top: the wall is stiffer near the base; pressing the flat sides of
    # the elliptic section (axis along the minor axis) is softer than pressing its ends
    assert (grid[0] > grid[-1]).all() and (grid[:, 0] > grid[:, 1]).all()
    rows = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    assert len(rows) == s["n_grasps"] == 4
    assert (tmp_path / "stiffness_maps.png").stat().st_size > 10_000


@EXPERIMENT_RUN
def test_sensitivity_engine_quick(tmp_path):
    pytest.importorskip("mujoco")
    argv = ["run", "sensitivity-engine", "--quick", "--out", str(tmp_path), "--set", "n_disturbances=3"]
    assert main([*argv, "--set", "workers=1"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    rows = {r["key"]: r for r in map(json.loads, (tmp_path / "rows.jsonl").read_text().splitlines())}
    held = np.array([rows[f"engine/0/{i}"]["held"] for i in range(3)])
    exact = np.array(rows["exact/0"]["pred"])
    with open(tmp_path / "trials.csv") as fh:
        trials = list(csv.DictReader(fh))
    assert [t["held"] == "True" for t in trials] == held.tolist()
    # each score is the rows' own predictions against the engine's verdicts
    assert s["exact_6dfw_vs_engine"]["accuracy"]["mean"] == pytest.approx(np.mean(exact == held))
    for m in ("point", "planar", "6dls"):
        pred = np.array(rows[f"model/0/{m}"]["pred"])
        assert s["models"][m]["vs_engine"]["accuracy"]["mean"] == pytest.approx(np.mean(pred == held)), m
        assert s["models"][m]["vs_exact_6dfw"]["accuracy"]["mean"] == pytest.approx(np.mean(pred == exact))
    assert s["engine_positive_fraction"]["mean"] == pytest.approx(held.mean())
    assert 0 < s["engine_seconds_per_trial"]["median"] <= s["engine_seconds_per_trial"]["worst"]
    assert set(s["thesis_claims"]) == {"6dls_over_planar"}
    # the verdict re-read at the run's own limits (5 mm, 5 deg) is the run's verdict; a looser
    # limit holds at least as many
    vt = s["verdict_thresholds"]
    assert vt["5mm_5deg"]["held_fraction"] == pytest.approx(held.mean())
    assert (
        vt["9mm_10deg"]["held_fraction"] >= vt["5mm_5deg"]["held_fraction"] >= vt["2mm_2deg"]["held_fraction"]
    )
    # a rerun resumes every row: no trial runs twice
    assert main([*argv, "--set", "workers=1"]) == 0
    assert json.loads((tmp_path / "summary.json").read_text())["n_resumed"] == len(rows)


@EXPERIMENT_RUN
def test_sensitivity_engine_bottles_quick(tmp_path):
    pytest.importorskip("mujoco")
    argv = ["run", "sensitivity-engine-bottles", "--quick", "--out", str(tmp_path), "--set", "n_grasps=3"]
    assert main([*argv, "--set", "workers=1"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    rows = {
        r["key"]: r
        for f in ("rows.jsonl", "models/rows.jsonl")
        for r in map(json.loads, (tmp_path / f).read_text().splitlines())
    }
    held = np.array([rows[f"engine/0/{i}"]["held"] for i in range(3)])
    exact = np.array([rows[f"models/0/{i}"]["exact"] for i in range(3)])
    # the engine and the models judged the same grasps, three distinct ones of the pool
    idx = [rows[f"engine/0/{i}"]["pool_index"] for i in range(3)]
    assert idx == [rows[f"models/0/{i}"]["pool_index"] for i in range(3)] and len(set(idx)) == 3
    assert s["pool"]["grasps"] > 3 and s["pool"]["grasps_used"] == 3
    for m in ("point", "planar", "6dls"):
        pred = np.array([rows[f"models/0/{i}"]["pred"][m] for i in range(3)])
        assert s["models"][m]["vs_engine"]["accuracy"]["mean"] == pytest.approx(np.mean(pred == held)), m
        assert s["models"][m]["vs_exact_6dfw"]["accuracy"]["mean"] == pytest.approx(np.mean(pred == exact))
    # a point contact resists no torsion: none of the lever disturbances (all carry tau_x)
    assert not any(rows[f"models/0/{i}"]["pred"]["point"] for i in range(3))
    # each FEM pad touches the bottle over a patch of the pad's size order (20 x 40 mm pad)
    areas = np.array([rows[f"models/0/{i}"]["contact_area_mm2"] for i in range(3)])
    assert ((areas > 20) & (areas < 800)).all()
    assert s["engine_positive_fraction"]["mean"] == pytest.approx(held.mean())
    assert s["engine_trials_not_simulated"] == 0
    with open(tmp_path / "trials.csv") as fh:
        assert [t["held"] == "True" for t in csv.DictReader(fh)] == held.tolist()
    # a rerun resumes every row of both checkpoints: no trial runs twice
    assert main([*argv, "--set", "workers=1"]) == 0
    assert json.loads((tmp_path / "summary.json").read_text())["n_resumed"] == len(rows)
    # more grasps than the pool holds is refused before any trial
    from workbench.experiments.sensitivity_engine_bottles import run

    big = build_config("sensitivity-engine-bottles", True, str(tmp_path / "big"), None, {"n_grasps": 10000})
    with pytest.raises(ValueError, match="more than the 10 grasps in the pool"):
        run(big)
    assert not (tmp_path / "big" / "rows.jsonl").exists()


@pytest.mark.jit_only(
    "(a)'s reference is our nonlinear pad FEM, minutes as pure Python; its kernels run "
    "without JIT in tests/test_fem_nonlinear.py"
)
def test_engine_validation_quick(tmp_path):
    pytest.importorskip("mujoco")
    assert main(["run", "engine-validation", "--quick", "--out", str(tmp_path), "--set", "workers=1"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    b = s["b_friction"]
    # (b): Coulomb within 5 % (the ramp's own onset bias is a few per cent, never early)
    assert 1.0 <= b["pulled_block"]["0.5/0.0"]["ratio"] < 1.05
    assert b["tilted_block"]["0.5"]["ratio"] == pytest.approx(1.0, abs=0.05)
    assert 0 <= b["creep_mm_per_s"]["0.5"] < 0.1  # held at half the slip load: creeps < 0.1 mm/s
    # (c): the pad's spin onset against μ Σ N_i |r_i| of its own contact forces
    assert s["c_torsion"]["ratio"] == pytest.approx(1.0, abs=0.1)
    # (a): the sphere R 10 mm at 0.25 mm within 10 % of our neo-Hookean pad, its settings recorded
    run = s["a_indentation"]["runs"]["sphere10/mujoco"]
    assert s["a_indentation"]["passes"]["sphere10/mujoco"] and run["max_abs_error"] <= 0.10
    assert s["d_shells"]["run"] is False
    # (e): grasp 0 held in all 5 real repeats, 19 dropped in all 5; the scores are the rows'
    e = s["e_reality"]
    assert e["n_trials"] == 10 and e["real_failures"] == 5
    held = {r["grasp"]: r["held"] for r in e["rows"]}
    assert e["true_positive_rate"] == float(held[0]) and e["true_negative_rate"] == float(not held[19])
    # the AUC ranks grasp 0's five real successes against grasp 19's five failures by excursion
    moved = {r["grasp"]: max(r["drift_mm"] / 5.0, r["turn_deg"] / 5.0) for r in e["rows"]}
    assert e["roc_auc"] == float(moved[0] < moved[19])
    assert s["settings"]["cone"] == "elliptic"


@EXPERIMENT_RUN
def test_sensitivity_quick(tmp_path):
    assert main(["run", "sensitivity", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert "no physical grasp data" in s["ground_truth"]
    assert 0.2 < s["truth_positive_fraction"] < 0.8  # both outcomes exercised
    ser = s["series"]
    lines = map(json.loads, (tmp_path / "rows.jsonl").read_text().splitlines())
    rows = {(r["series"], r["x"], r["model"]): r for r in lines if "x" in r}
    for m in ("soft_point", "planar", "6dls", "6dfc"):
        # predictions shift with μ: more positives with a larger assumed μ
        assert rows[("mu_offset", 0.2, m)]["positives"] > rows[("mu_offset", -0.2, m)]["positives"], m
        # recall does not fall with k (a flatter pressure gives more torsional friction)
        assert ser["k"][m]["recall"][-1] >= ser["k"][m]["recall"][0], m
    # at the true parameters the 6D models recall at least what point and planar models do
    at = {m: ser["k"][m] for m in ser["k"] if m != "x"}
    for m in ("6dls", "6dfc"):
        assert at[m]["recall"][0] >= max(at["point"]["recall"][0], at["planar"]["recall"][0])
        assert at[m]["precision"][0] >= 0.8
    assert set(s["ms_per_grasp"]) >= {"point", "soft_point", "planar", "6dls", "6dfc"}
    assert (tmp_path / "fig_4_4_sensitivity.png").stat().st_size > 10_000
    mp = s["at_matched_precision"]
    assert mp["levels"] == [0.9, 0.95, 0.98] and set(mp["recall"]) == set(s["ms_per_grasp"])
    # the point contact cannot resist τ_x at any threshold; soft and 6D models can
    assert all(np.isnan(r) or r < 0.5 for r in mp["recall"]["point"])
    assert mp["recall"]["6dls"][0] > 0.8
    assert (tmp_path / "precision_recall.png").stat().st_size > 10_000
    # training distributions (which sampler trains the best limit surface): each sampler's 6DLS
    # margins against the noise-free exact margins; the model's own error is a few percent, well
    # below the noisy truth's spread
    td = s["training_distribution"]["6dls"]
    assert set(td) == {"thesis", "thesis-code", "mix"}
    for kind, e in td.items():
        assert e["vs_exact_nominal"]["n"] >= 30, kind
        assert 0 < e["vs_exact_nominal"]["median_abs_log_ratio"] < 0.05, (kind, e)
    # the default sampler is "mix": the plain 6dls margins are the @mix ones, computed once
    rows = {r["key"]: r for r in map(json.loads, (tmp_path / "rows.jsonl").read_text().splitlines())}
    assert rows["margin/6dls"]["margins"] == rows["margin/6dls@mix"]["margins"]
    assert rows["margin/6dls@mix"]["same_inputs_as"] == "margin/6dls"


@EXPERIMENT_RUN
def test_sensitivity_rows_with_the_same_inputs_are_computed_once(tmp_path):
    """The margin with the default training sampler is the "mix" row, and the zero μ and length
    offsets are the k row at k_true: each computed apart gives the same numbers, so a run
    computes one and checkpoints it under every key (marked), also when it resumes after a kill
    between the two."""
    from workbench.grasp.sensitivity_rows import sensitivity_row
    from workbench.runner.experiment_config import build_config

    sets = {
        "n_disturbances": 8,
        "models": ["planar", "6dls"],
        "training_models": ["6dls"],
        "training_samplers": ["thesis", "mix"],
        "k_values": [2.0, 2.4],
        "mu_offsets": [0.0, 0.2],
        "length_offsets": [0.0],
        "robust_disturbances": 4,
    }
    cfg = build_config("sensitivity", True, str(tmp_path), None, sets)
    assert cfg["k_true"] == 2.4
    # the premise, computed apart
    margins = [sensitivity_row(("margin", "6dls", s), cfg)["margins"] for s in (None, "mix")]
    assert margins[0] == margins[1]
    preds = [
        sensitivity_row(("setting", s, x, "6dls"), cfg)["pred"]
        for s, x in [("k", 2.4), ("mu_offset", 0.0), ("length_offset", 0.0)]
    ]
    assert preds[0] == preds[1] == preds[2] and 0 < sum(preds[0]) < len(preds[0])
    argv = ["run", "sensitivity", "--quick", "--out", str(tmp_path), "--set", "workers=1"]
    argv += [a for k, v in sets.items() for a in ("--set", f"{k}={json.dumps(v)}")]
    assert main(argv) == 0
    lines = (tmp_path / "rows.jsonl").read_text().splitlines()
    rows = {r["key"]: r for r in map(json.loads, lines)}
    twins = {
        "margin/6dls@mix": "margin/6dls",
        "mu_offset/0.0/planar": "k/2.4/planar",
        "mu_offset/0.0/6dls": "k/2.4/6dls",
        "length_offset/0.0/planar": "k/2.4/planar",
        "length_offset/0.0/6dls": "k/2.4/6dls",
    }
    assert {k for k, r in rows.items() if "same_inputs_as" in r} == set(twins)
    for twin, first in twins.items():
        assert rows[twin]["same_inputs_as"] == first
        for field in ("margins", "precision", "recall", "positives"):
            assert rows[twin].get(field) == rows[first].get(field), (twin, field)
    assert rows["mu_offset/0.0/6dls"]["series"] == "mu_offset" and rows["mu_offset/0.0/6dls"]["x"] == 0.0
    # killed after the first rows, before their twins were copied: the resume copies them
    (tmp_path / "rows.jsonl").write_text(
        "\n".join(x for x in lines if json.loads(x)["key"] not in twins) + "\n"
    )
    assert main(argv) == 0
    again = (tmp_path / "rows.jsonl").read_text().splitlines()[len(lines) - len(twins) :]
    assert sorted(json.loads(x)["key"] for x in again) == sorted(twins)  # nothing else recomputed


@pytest.mark.parametrize(
    "sets, match",
    [
        ({"mu": 0.0}, "mu = 0 has no friction wrench"),
        ({"heights": [5.0]}, "heights are fractions of the object.s height in \\(0, 1\\)"),
        ({"nu": 0.5}, r"--set nu=0.5: nu must be a Poisson ratio in \(-1, 0.5\)"),
        (
            {"pad": {"width": 20.0}},
            r".* pad\['width'\] \[m\] must be a pad size .* probably in millimetres — pass 0.02",
        ),
        ({"deltas_mm": [7.0]}, "deltas_mm are jaw displacements"),
        ({"n_wrenches": 10}, "n_wrenches must be >= 126"),
    ],
)
def test_fem_fitting_refuses_physical_nonsense_before_any_work(sets, match):
    with pytest.raises(SystemExit, match=f"fem-fitting: {match}"):
        build_config("fem-fitting", True, None, None, sets)


@EXPERIMENT_RUN
def test_minimal_work_quick(tmp_path):
    """The quick run's headline numbers (skips without the CC BY-NC data folder)."""
    from workbench.experiments.minimal_work import DEFAULT_CONFIG, THESIS_TABLE_4_6

    if not (Path(DEFAULT_CONFIG["data_dir"]) / "stiffness_maps" / "plastic_cup.json").exists():
        pytest.skip("deformable_objects data not present")
    assert main(["run", "minimal-work", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["thesis_table_4_6"] == THESIS_TABLE_4_6
    assert s["thesis_table_4_6"]["lift_and_rotate"]["q_work"]["All"] == 0.789  # thesis Table 4.6
    for task in ("vertical_lifting", "lift_and_rotate"):
        for metric in ("q_robust", "q_force", "q_work"):
            acc = s["table_4_6"][task][metric]
            assert set(acc) == {"plastic_cup", "mustard", "shampoo", "All"}
            assert 0.0 <= acc["All"] <= 1.0
    assert "SIMULATED" in s["ground_truth"] and s["n_grasps"] >= 12
    v = s["stiffness_validation"]
    # the cup's measured U-shape (stiff base and rolled lip, soft middle) needs the lip ring:
    # a free top edge gave Spearman -0.18 over its 40 grasps
    assert v["plastic_cup"]["spearman_all"] > 0.6
    for name in ("plastic_cup", "mustard", "shampoo"):
        assert 0.05e9 < v[name]["calibrated"]["E_effective_Pa"] < 2.5e9  # thinner or softer than PET
        loo = s["stiffness_interpolation"][name]
        assert loo["median_abs_log_error"] < loo["baseline_median_abs_log_error"]
    # held-out class counts per object add up to the held-out grasps
    held = s["class_balance"]["vertical_lifting"]["held_out"]
    assert sum(a + b for a, b in held.values()) == s["n_test"]
    # scope 9: the nonlinear wall's work at every shampoo candidate (quick: coarse mesh)
    nl = s["beyond_thesis_nonlinear_work"]
    assert nl["objects"] == ["shampoo"] and nl["n_grasps"] == s["n_grasps_per_object"]["shampoo"]
    assert nl["n_curves"] >= 1
    for task in ("vertical_lifting", "lift_and_rotate"):
        t = nl["table"][task]
        assert set(t) == {
            "q_work_map",
            "q_work_fem_linear",
            "q_work_fem_nonlinear",
            "W_nonlinear_over_linear",
        }
        # the nonlinear wall is softer at these closings (wall-nonlinear: 0.63-1.05 x the linear
        # stiffness on shampoo), so its work is at least comparable; a unit slip would be 1e3 off
        assert 0.5 < t["W_nonlinear_over_linear"]["median"] < 5.0


@EXPERIMENT_RUN
def test_minimal_work_engine_quick(tmp_path):
    """Table 4.6's candidates judged by MuJoCo; the scores are the trials' own (skips
    without the CC BY-NC data folder or MuJoCo)."""
    pytest.importorskip("mujoco")
    from workbench.experiments.minimal_work import DEFAULT_CONFIG

    if not (Path(DEFAULT_CONFIG["data_dir"]) / "stiffness_maps" / "plastic_cup.json").exists():
        pytest.skip("deformable_objects data not present")
    # two of the three objects: each has a turned grasp that fails in the quick run, and every
    # trial is a MuJoCo simulation of seconds (the third object is judged by make reproduce)
    objects = '["mustard", "shampoo"]'
    argv = ["run", "minimal-work-engine", "--quick", "--out", str(tmp_path), "--set", "workers=1"]
    argv += ["--set", f"objects={objects}"]
    assert main(argv) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    with open(tmp_path / "trials.csv") as fh:
        trials = list(csv.DictReader(fh))
    with open(tmp_path / "metrics" / "grasps.csv") as fh:
        metrics = {(r["object"], r["grasp"]): r for r in csv.DictReader(fh)}
    assert len(trials) == 2 * s["n_grasps_judged"] == 2 * 2 * 2  # 2 objects x 2 grasps x 2 tasks
    held = {
        t: np.array([r["engine_held"] == "True" for r in trials if r["task"] == t])
        for t in ("vertical_lifting", "lift_and_rotate")
    }
    # turning the object 90 deg about the grasp axis adds the weight's torque: never easier
    assert held["lift_and_rotate"].sum() <= held["vertical_lifting"].sum()
    assert held["lift_and_rotate"].sum() < len(held["lift_and_rotate"])  # some turned grasp fails
    for t in ("vertical_lifting", "lift_and_rotate"):
        rows = [r for r in trials if r["task"] == t]
        truth = held[t]
        old = np.array([r["old_truth"] == "True" for r in rows])
        assert s["old_truth_vs_engine"][t]["agreement"] == pytest.approx(np.mean(old == truth))
        # q_robust on the held-out grasps (minimal-work's split rule), by hand
        split = np.random.default_rng(1).random(len(rows)) < 0.5
        q = np.array([float(metrics[r["object"], r["grasp"]][f"{t}_q_robust"]) for r in rows])
        p, y = q[~split] >= 0.5, truth[~split]
        ba = np.mean([np.mean(p[y == c] == c) for c in (True, False) if (y == c).any()])
        assert s["table_4_6_engine"][t]["q_robust"]["All"] == pytest.approx(ba)
    assert 0 < s["engine_seconds_per_grasp"]["median"] <= s["engine_seconds_per_grasp"]["worst"] < 120
    assert "rigid" in s["cannot_judge"] and "REACH profiles" in s["does_not_share"]
    # a larger sample or a new split resumes every trial already run
    assert main([*argv, "--set", "n_bootstrap=300"]) == 0
    # (a checkpoint row holds both tasks' trials of one grasp)
    assert json.loads((tmp_path / "summary.json").read_text())["n_resumed"] == len(trials) // 2


@pytest.mark.parametrize(
    "sets, match",
    [
        ({"n_grasps": 1}, "n_grasps must be an integer >= 2"),
        ({"n_bootstrap": 10}, "n_bootstrap must be an integer >= 100"),
        ({"max_turn_deg": 0.5}, "max_turn_deg"),
        ({"engine_force": 10_000.0}, "engine_force"),
    ],
)
def test_minimal_work_engine_refuses_before_any_trial(sets, match):
    from workbench.experiments.minimal_work import DEFAULT_CONFIG

    if not (Path(DEFAULT_CONFIG["data_dir"]) / "meshes" / "mustard.obj").exists():
        pytest.skip("deformable_objects data not present")
    with pytest.raises(SystemExit, match=match):
        build_config("minimal-work-engine", True, None, None, sets)


@EXPERIMENT_RUN
def test_wall_nonlinear_quick(tmp_path):
    """The quick run's headline numbers — at the calibrated E and the
    closings the cup is measured at, the nonlinear wall is softer than the linear one
    (0.74x at 3 N on the quick mesh); both jaws press alike (skips without the data)."""
    from workbench.experiments.wall_nonlinear import DEFAULT_CONFIG

    if not (Path(DEFAULT_CONFIG["data_dir"]) / "stiffness_maps" / "plastic_cup.json").exists():
        pytest.skip("deformable_objects data not present")
    assert main(["run", "wall-nonlinear", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    (g,) = s["grasps"]
    assert 0.05e9 < s["E_linear_calibrated_Pa"] < 2.5e9
    assert 0.5 < g["ratio_nl_lin"] < 0.95
    assert g["closing_linear_mm"] > 2.0  # many wall thicknesses: the regime in question
    assert g["jaw_force_imbalance"] < 0.02
    assert s["calibrated_on_these_grasps"]["nonlinear"]["median_abs_log_ratio"] < 1e-6  # one grasp, own E
    assert (tmp_path / "fig_force_closing.png").stat().st_size > 10_000


@EXPERIMENT_RUN
def test_peers_quick(tmp_path):
    """Every peer on the same contacts, checked against what each must give."""
    assert main(["run", "peers", "--quick", "--out", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    rows = list(csv.DictReader((tmp_path / "peers.csv").open()))
    at = {(r["case"], r["peer"], float(r["delta_mm"])): r for r in rows}
    P = s["peers"]
    for peer in ("condensed", "linear", "foundation", "mujoco_hertz", "mujoco_diameter"):
        for case in ("sphere", "cylinder"):
            for key in (
                "force_rel_err",
                "area_rel_err",
                "pressure_rel_l2",
                "torsion_rel_err",
                "margin_rel_err",
                "ls_rel_err",
            ):
                assert key in P[peer][case]
            assert P[peer][case]["ms_per_query"] > 0
    # a point contact's cone slice spans 3 of 6 dimensions: no fitted 6DLS; the condensed and the
    # full-mesh pad give one profile, so one fitted 6DLS and one error
    assert P["mujoco_hertz"]["sphere"]["ls_rel_err"] is None
    for case in ("sphere", "cylinder"):
        c, lin = P["condensed"][case]["ls_rel_err"], P["linear"][case]["ls_rel_err"]
        assert c == pytest.approx(lin, rel=1e-4) and 0 < P["neo-Hookean"][case]["ls_rel_err"] < 1
    # the condensed and the full-mesh linear pad solve one linear problem: equal forces and fields
    for case in ("sphere", "cylinder"):
        c, lin = at[(case, "condensed", 1.0)], at[(case, "linear", 1.0)]
        assert float(c["force_N"]) == pytest.approx(float(lin["force_N"]), rel=1e-6)
        assert float(c["pressure_rel_l2"]) == pytest.approx(float(lin["pressure_rel_l2"]), rel=1e-6)
    # Hertz's exact torsion length 3πa/16 (6DFW of its profile, per jaw force: 1 - O(a²/R²)), and
    # MuJoCo's cone given the same 3πa/16 by construction
    R, d = 0.015, 1e-3
    tl = 3 * np.pi * np.sqrt(R * d) / 16 * 1e3
    assert float(at[("sphere", "hertz", 1.0)]["torsion_length_mm"]) == pytest.approx(tl, rel=R * d / R / R)
    assert float(at[("sphere", "mujoco_hertz", 1.0)]["torsion_length_mm"]) == pytest.approx(tl, rel=1e-12)
    # the Winkler foundation k = E/h against its closed form kV on the sphere (the jaw reads the
    # net force, lower by the patch's tilt: within δ/R), and Drake's hydroelastic box, the same law
    E, h = 1e6, 0.005
    kV = E / h * np.pi * d * d * (3 * R - d) / 3
    f_found = float(at[("sphere", "foundation", 1.0)]["force_N"])
    assert kV * (1 - d / R) < f_found < kV
    if "drake" in P:
        f_drake = float(at[("sphere", "drake", 1.0)]["force_N"])
        res = 0.05 * R  # quick config: resolution R/20, the force low by ~res²/(4Rδ)
        assert f_drake == pytest.approx(f_found, rel=res * res / (4 * R * d) + 0.01)
    # a user's MuJoCo torsion from the patch "diameter" over-states the capacity (optimistic
    # margins), the Hertz patch radius under-states a cylinder's line contact (pessimistic)
    assert P["mujoco_diameter"]["sphere"]["margin"]["median_log_ratio"] > 0
    assert P["mujoco_hertz"]["cylinder"]["margin"]["median_log_ratio"] < 0
    assert P["mujoco_hertz"]["cylinder"]["torsion_rel_err"] < -0.5
    # where Hertz applies (the requirement: within 3 %): the layer's stiffening halves with a/H, and the
    # half-space limit it extrapolates to is Hertz's force
    hb = s["hertz_half_space"]
    e20, e40 = hb["force_rel_err"]
    assert 0 < e40 < e20 and abs(hb["extrapolated_force_rel_err"]) < 0.03
    assert (tmp_path / "runtime_vs_error.png").stat().st_size > 10_000
    assert set(s["vs_drake"]) == ({"sphere", "cylinder"} if "drake" in P else set())


def test_peers_bottle_case_is_placed_as_fem_fitting_places_it():
    """The thesis bottle in the peers' pad frame: touching at δ = 0 (the face's closest node at
    distance 0), its section centre straight above the pad at about h + A (the jaw approaches along
    the major semi-axis A), MuJoCo's curvature radius B²/A; Drake's mesh of it lies on the analytic
    wall to within its chord sag (2π A / n_theta)² / (8 ρ) at the contact."""
    from workbench.experiments.peers import DEFAULT_CONFIG
    from workbench.fem.bottle import Bottle, bottle_family
    from workbench.fem.pad import PadFace
    from workbench.peers.pad_cases import bottle_mesh, setup_case

    geom, mat, pose, c, rho = setup_case("bottle", DEFAULT_CONFIG)
    bottle = Bottle(bottle_family(24, 8, 0)[0])
    z = 0.5 * bottle.params.height
    _, A, B, _ = bottle.section(z)
    face = PadFace.of(geom, mat).face_xy
    X = np.column_stack([face, np.full(len(face), geom.thickness)])
    d, _ = pose.signed_distance(X)
    assert abs(d.min()) < 1e-12
    # straight above the pad, at h + A or a little more: the face touches the wall's outermost point
    # within its 20 mm height, which a bulging wall puts beyond the section's A (0.14 % here)
    assert c[:2] == pytest.approx([0.0, 0.0], abs=1e-9)
    assert A <= c[2] - geom.thickness <= 1.01 * A
    assert rho == pytest.approx(B * B / A)
    mesh = bottle_mesh(pose, DEFAULT_CONFIG["bottle"]["mesh"])
    n_theta = DEFAULT_CONFIG["bottle"]["mesh"][0]
    sag = (2 * np.pi * A / n_theta) ** 2 / (8 * rho)
    near = X[d < 1e-3]  # the face nodes within 1 mm of the wall
    assert np.abs(mesh.signed_distance(near)[0] - pose.signed_distance(near)[0]).max() < 2 * sag
    with pytest.raises(SystemExit, match="bottle must be"):
        build_config("peers", True, None, None, {"bottle": {"index": 30, "height": 0.5, "mesh": [64, 64]}})


def test_fem_fitting_gives_a_task_a_grasp_on_long_runs(tmp_path):
    """From ``config.RUN.grasp_tasks_from`` grasps a task holds a grasp's remaining jaw
    displacements (solved once, in order), below it one profile; either way every profile to
    do is in exactly one task and the tasks with the protocol ablation come first."""
    from workbench import config
    from workbench.experiments.fem_fitting import row_tasks
    from workbench.limit_surface.profile_fits import ablation_due

    cfg = build_config("fem-fitting", True, str(tmp_path), None, {"ablation_every": 5})
    todo = [(j, 0, 0.5, "major", 0.0, [0, 1, 2]) for j in range(4)] + [(4, 1, 0.5, "minor", 1.5, [2])]
    for threshold, per_task in ((5, 3), (6, 1)):
        with config.override(grasp_tasks_from=threshold):
            tasks = row_tasks(todo, cfg)
        assert {t[0] for t in tasks} == {"rows"}
        profiles = sorted((t[1][0], k) for t in tasks for k in t[1][-1])
        assert profiles == sorted((job[0], k) for job in todo for k in job[-1])
        assert max(len(t[1][-1]) for t in tasks) == per_task
        # profile k of grasp j is the (3 j + k)-th of the sweep: 0, 5 and 10 (grasps 0, 1, 3) get the
        # ablation, and their tasks come first
        ablated = [any(ablation_due(3 * t[1][0] + k, 5) for k in t[1][-1]) for t in tasks]
        assert ablated == [True] * 3 + [False] * (len(tasks) - 3)


def test_minimal_work_wall_rows_are_shared_by_runs_at_the_same_wall(tmp_path, monkeypatch):
    """The wall squeezes (the measured grasps' FEM and every candidate's) are computed once per
    machine for a wall's settings, in tasks of WALL_ROWS_PER_TASK grasps of one object: a second
    run (another output folder, another profile source) reads the shared rows, checkpoints them
    as its own, and computes nothing; another E or another mesh file computes again."""
    import workbench.fem.grasp_walls as gw
    import workbench.fem.wall_grasps as wg
    from workbench.experiments import minimal_work as mw
    from workbench.runner.results import Checkpoint

    data = tmp_path / "data"
    (data / "meshes").mkdir(parents=True)
    (data / "stiffness_maps").mkdir()
    (data / "meshes" / "cup.obj").write_text("v 0 0 0\n")
    (data / "stiffness_maps" / "cup.json").write_text("{}")
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "cache"))
    calls, wall = [], {"offset": 0.0}
    geo = type("Geo", (), {"surface": None, "z_range": (0.0, 1.0)})()
    monkeypatch.setattr(gw, "linear_wall", lambda path, settings: (geo, wall["offset"]))

    def fake_stiffness_at(w, surface, P, **kw):
        ids = kw["grasp_ids"]
        calls.append(list(ids))
        assert len(P) == 2 * len(ids)
        # the grasp's first jaw point (row j) and second (row j + m) reach the squeeze
        return [{"stiffness": 100.0 + i + w, "x": [P[j, 0], P[j + len(ids), 0]]} for j, i in enumerate(ids)]

    monkeypatch.setattr(wg, "stiffness_at", fake_stiffness_at)
    n_fem, n_cand = 4, mw.WALL_ROWS_PER_TASK + 3  # the candidates in two tasks
    L = np.arange(6 * n_fem, dtype=float).reshape(2 * n_fem, 3)  # jaw A rows, then jaw B rows
    C = 1000 + np.arange(6 * n_cand, dtype=float).reshape(2 * n_cand, 3)
    base = {
        "data_dir": str(data),
        "E": 1e9,
        "nu": 0.4,
        "thickness": 5e-4,
        "mesh": [8, 4],
        "jaw": [0.02, 0.04],
        "workers": 1,
        "scheduler": "",
    }

    def run(config, out, offset=0.0):
        wall["offset"] = offset
        ckpt = Checkpoint(tmp_path / out / "rows.jsonl", {**config, "out": out})
        rows = mw.wall_rows(ckpt, {("cup", "fem"): L, ("cup", "wall"): C}, config)
        own = ("key", "config_hash")  # the run's checkpoint fields
        return {k: [{a: b for a, b in r.items() if a not in own} for r in v] for k, v in rows.items()}, ckpt

    first, _ = run({**base, "profiles": "reach"}, "a")
    assert [r["stiffness"] for r in first["cup", "fem"]] == [100.0, 101.0, 102.0, 103.0]
    assert [r["x"] for r in first["cup", "fem"]] == [[L[i, 0], L[i + n_fem, 0]] for i in range(n_fem)]
    assert [r["x"] for r in first["cup", "wall"]] == [[C[i, 0], C[i + n_cand, 0]] for i in range(n_cand)]
    assert calls == [
        [0, 1, 2, 3],
        list(range(mw.WALL_ROWS_PER_TASK)),
        list(range(mw.WALL_ROWS_PER_TASK, n_cand)),
    ]
    second, ckpt = run({**base, "profiles": "fem"}, "b", offset=50.0)  # a different wall would show
    assert second == first and len(calls) == 3
    # checkpointed under this run's own key: a resume of run b keeps them
    assert len(Checkpoint.peek(ckpt.path, {**base, "profiles": "fem", "out": "b"})) == n_fem + n_cand
    third, _ = run({**base, "E": 2e9}, "c", offset=1.0)
    assert [r["stiffness"] for r in third["cup", "fem"]] == [101.0, 102.0, 103.0, 104.0] and len(calls) == 6
    (data / "meshes" / "cup.obj").write_text("v 0 0 1\n")
    gw.mesh_digest.cache_clear()
    run(base, "d")
    assert len(calls) == 9


@EXPERIMENT_RUN
def test_physical_trials_quick(tmp_path):
    """The REACH YuMi trials (quick: grasps 0, 2, 5, 19; 3 models; N_r = 3, 2 seeds): the
    contact recomputed from each gripper pose and scored against the real outcomes."""
    out = tmp_path / "pt"
    assert main(["run", "physical-trials", "--quick", "--out", str(out), "--set", "workers=1"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["n_trials"] == 20 and s["n_grasps"] == 4
    assert s["successes_per_grasp"] == {"0": 5, "2": 1, "5": 5, "19": 0}
    # grasp 0's jaws are 3.0° off its faces: the free cube turns by that and meets both pads flat
    assert abs(s["settle"]["tilt_deg"]["0"] - 3.02) < 0.05
    # a 3 g cube in a 20 N grip: every model but the hard point holds it at every nominal pose
    assert s["not_held_nominal"] == {"soft_point": 0, "6dls": 0, "6dfc": 0}
    rows = list(csv.DictReader((out / "grasps.csv").open()))
    q = {int(r["grasp"]): float(r["robust_seed0/6dls"]) for r in rows}
    # grasp 19's pad overlaps its face by a 2 mm strip: pose noise slides it off in a third of
    # the samples; grasp 5's pad lies wholly on its face
    assert q[19] < 0.8 < 0.99 < q[5]
    # AUC of the robust quality by hand: successes 5 x g0, 1 x g2, 5 x g5 against failures
    # 4 x g2, 5 x g19, with q(g19) < q(g2) < q(g0) < q(g5): (45 + 45 + 5 + 4 / 2) / 99
    assert abs(s["scores"]["6dls"]["robust_seed0"]["roc_auc"] - 97 / 99) < 1e-12


@pytest.mark.parametrize(
    "sets, match",
    [
        ({"n_grasps": 1}, r"^minimal-work-engine: n_grasps must be an integer >= 2 .*; got 1$"),
        ({"n_bootstrap": 10}, r"^minimal-work-engine: n_bootstrap must be an integer >= 100 .*; got 10$"),
        ({"max_turn_deg": 0.1}, r"^minimal-work-engine: max_turn_deg .*0\.1"),
        ({}, r"^minimal-work-engine: plastic_cup: .*nowhere.* not found — set data_dir"),  # the control
    ],
)
def test_minimal_work_engine_checks_its_own_keys_before_the_data(sets, match, tmp_path):
    """n_grasps=1, n_bootstrap=10 and max_turn_deg=0.1 were hidden behind "data_dir ... not
    found" where the CC BY-NC data is absent: the experiment's own keys are judged first."""
    sets = {"data_dir": str(tmp_path / "nowhere"), **sets}
    with pytest.raises(SystemExit, match=match):
        build_config("minimal-work-engine", True, str(tmp_path / "out"), None, sets)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("key", ["mus", "pull_angles_deg", "creep_fractions", "indenters", "depths_mm"])
def test_engine_validation_refuses_an_empty_probe_list_before_any_work(key, tmp_path):
    """``mus=[]`` ran the probes and REACH trials, then failed with "min() arg is an empty
    sequence"; ``reach_grasps=[]`` means all 25 and stays accepted."""
    with pytest.raises(SystemExit, match=rf"^engine-validation: {key} is empty \(.*\): give at least one"):
        build_config("engine-validation", True, str(tmp_path / "out"), None, {key: []})
    assert not (tmp_path / "out").exists()
    assert build_config("engine-validation", True, None, None, {"reach_grasps": []})["reach_grasps"] == []


def test_engine_validation_refuses_depths_deeper_than_its_pad_without_blaming_the_unit(tmp_path):
    """``depths_mm=[6]`` (in mm, deeper than the 5 mm pad) was told "displacements are in metres"."""
    import warnings

    from workbench.fem.pad import PadGeometry
    from workbench.plausible import ImplausibleWarning

    assert PadGeometry().thickness == 0.005  # both of (a)'s pads: the default layer
    for depths in ([6.0], [0.5, 5.0]):
        with pytest.raises(SystemExit) as exc, warnings.catch_warnings():
            warnings.simplefilter("ignore", ImplausibleWarning)  # 6 mm: above a usual compression
            build_config("engine-validation", True, str(tmp_path / "out"), None, {"depths_mm": depths})
        msg = str(exc.value.code)
        assert f"depths_mm {depths[-1:]} reach (a)'s pad thickness of 5 mm" in msg, msg
        assert "metres" not in msg and "below 5 mm" in msg
    assert build_config("engine-validation", True, None, None, {"depths_mm": [4.9]})["depths_mm"] == [4.9]


@EXPERIMENT_RUN
def test_grasp_dataset_quick(tmp_path):
    """§4.2.2 on two meshes of the test's own: every candidate a row of the Parquet table, scored by
    every model; Fig 4.8 on the flat box, where the pads' centroid lies 20 mm above the jaw bottom
    — above the 20 mm box, so the centre axis keeps no grasp and the jaw-bottom axis keeps the
    side grasps at least 5 mm up; a second run resumes every row."""
    import pandas as pd
    import trimesh

    box = trimesh.creation.box([0.08, 0.05, 0.02])
    box.apply_translation([0, 0, 0.01])
    box.export(tmp_path / "flat_box.obj")
    cyl = trimesh.creation.cylinder(radius=0.025, height=0.06, sections=48)
    cyl.apply_translation([0, 0, 0.03])
    cyl.export(tmp_path / "can.obj")
    out = tmp_path / "out"
    argv = ["run", "grasp-dataset", "--quick", "--out", str(out), "--set", "workers=1"]
    argv += ["--set", f"meshes={tmp_path}/*.obj"]
    assert main(argv) == 0
    s = json.loads((out / "summary.json").read_text())
    t = pd.read_parquet(out / "table.parquet")
    models = ["soft_point", "planar", "6dls", "6dfc"]
    assert s["report_object"]["name"] == "flat_box_lying"
    assert s["report_object"]["flatness"] == pytest.approx(0.02 / 0.08)
    assert t.groupby("object").size().to_dict() == {"can": 3, "flat_box": 3, "flat_box_lying": 12}
    assert s["fig_4_8"]["centre"]["kept"] == 0 < s["fig_4_8"]["jaw_bottom"]["kept"]
    rep = t[t.object == "flat_box_lying"]
    for m in models:
        q = t[f"q_{m}"].to_numpy()
        assert np.allclose(q * 5, np.round(q * 5), atol=1e-12) and ((q >= 0) & (q <= 1)).all()
        assert s["fig_4_9"][m]["max_q"] == pytest.approx(rep[f"q_{m}"].max())
    # the report object's grasps sit at least the clearance above the table, nearly horizontal
    p1, p2 = np.stack(rep.p1.to_numpy()), np.stack(rep.p2.to_numpy())
    assert (np.minimum(p1[:, 2], p2[:, 2]) >= 0.005 - 1e-9).all()
    axis = p2 - p1
    assert (np.abs(axis[:, 2]) / np.linalg.norm(axis, axis=1) <= np.sin(np.radians(10)) + 1e-9).all()
    th = s["throughput"]
    scored = t[t.status == "scored"]
    total = scored.t_contact_ms + sum(scored[f"t_{m}_build_ms"] + scored[f"t_{m}_q_ms"] for m in models)
    assert th["all_models_ms"] == pytest.approx(total.median())  # a row's time, all of it
    assert s["cost_500k"]["core_hours"] == pytest.approx(
        total.mean() * 5e5 / 3.6e6
    )  # totals scale with the mean
    assert (out / "fig_4_9_quality_map.png").stat().st_size > 10_000
    assert (out / "fig_4_9_best_grasps.png").stat().st_size > 10_000
    assert main(argv) == 0
    again = pd.read_parquet(out / "table.parquet")
    assert json.loads((out / "summary.json").read_text())["n_resumed"] == len(t)
    keep = [c for c in t.columns if not c.startswith("t_")]
    pd.testing.assert_frame_equal(t[keep], again[keep])


def test_grasp_dataset_refuses_careless_settings_before_any_row(tmp_path, capsys):
    """Found by a new-user trial: a model named twice, a mass no object that size has, a flat
    object the gripper cannot open around (refused before any row, not at the end); a list of
    paths on the command line is read as one."""
    import re

    import trimesh

    box = trimesh.creation.box([0.08, 0.05, 0.02])
    box.export(tmp_path / "box.obj")
    big = trimesh.creation.box([0.3, 0.2, 0.15])  # wider than the 0.1 m opening both ways
    big.export(tmp_path / "big.obj")
    base = ["run", "grasp-dataset", "--quick", "--out", str(tmp_path / "o"), "--set", "workers=1"]
    one = ["--set", f"meshes={tmp_path}/box.obj"]
    for sets, match in (
        ([*one, "--set", 'models=["6dls","6dls"]'], "each once"),
        # a third trial: the model's name in capitals got no hint
        ([*one, "--set", 'models=["6DLS","soft-point"]'], "did you mean '6dls' for '6DLS', 'soft_point' for"),
        ([*one, "--set", "mass_kg=5.0"], r"mass_kg 5.0 on box .*grams"),
        (
            ["--set", f"meshes={tmp_path}/big.obj", "--set", "max_candidates=2000"],
            "big_lying, has 0 top grasp",
        ),
    ):
        with pytest.raises(SystemExit):
            main([*base, *sets])
        assert re.search(match, capsys.readouterr().err), match
    # a mesh in millimetres, one in centimetres, an open mesh and a folder are refused naming the
    # file once, with the remedy a command line has (re-export the file; no units= or allow_scale)
    mm = trimesh.creation.box([80.0, 50.0, 20.0])
    mm.export(tmp_path / "mm_box.obj")
    trimesh.creation.box([8.0, 5.0, 20.0]).export(tmp_path / "cm_box.obj")
    open_box = trimesh.creation.box([0.08, 0.05, 0.02])
    open_box.update_faces(np.arange(len(open_box.faces)) > 0)
    open_box.export(tmp_path / "open_box.obj")
    for sets, match in (
        (
            ["--set", f"meshes={tmp_path}/mm_box.obj"],
            rf"error: mm_box \({tmp_path}/mm_box.obj\) spans 80 m .*probably in millimetres: re-export the "
            r"file in metres \(scale it by 0.001.*; or in centimetres \(then 0.8 m across\)",
        ),
        (
            ["--set", f"meshes={tmp_path}/cm_box.obj"],
            r"cm_box .* spans 20 m .*probably in millimetres: .*; or in centimetres \(then 0.2 m across\): "
            r"re-export the file in metres \(scale it by 0.01",
        ),
        (["--set", f"meshes={tmp_path}/open_box.obj"], r"open_box \(.*open_box.obj\):? .*watertight"),
        (["--set", f"meshes={tmp_path}"], "is not a file"),
    ):
        with pytest.raises(SystemExit):
            main([*base, *sets])
        err = capsys.readouterr().err
        assert re.search(match, err), match
        assert "units=" not in err and "allow_scale" not in err and err.count("_box (") <= 1
    assert not (tmp_path / "o" / "rows.jsonl").exists()
    from workbench.experiments.grasp_dataset import DEFAULT_CONFIG, mesh_files

    listed = json.dumps([str(tmp_path / "box.obj"), str(tmp_path / "big.obj")])
    assert list(mesh_files({**DEFAULT_CONFIG, "meshes": listed})) == ["big", "box"]
    # a second trial: a path listed twice, two files of one name, a mesh that is not .obj
    (tmp_path / "other").mkdir()
    box.export(tmp_path / "other" / "box.obj")
    box.export(tmp_path / "box.stl")
    for paths, match in (
        ([tmp_path / "box.obj", tmp_path / "box.obj"], "more than once"),
        ([tmp_path / "box.obj", tmp_path / "other" / "box.obj"], r"share a name .*'box'"),
        ([tmp_path / "box.stl"], r"must be \.obj files"),
    ):
        with pytest.raises(ValueError, match=match):
            mesh_files({**DEFAULT_CONFIG, "meshes": json.dumps([str(p) for p in paths])})
