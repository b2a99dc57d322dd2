"""workbench.config: tolerances and defaults are read when a function runs, so override() and
configure() reach every later call — and no library module binds them at import."""

from __future__ import annotations

import ast
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest

from workbench import config
from workbench.limit_surface.normalize import pca_subspace
from workbench.twists import sample_twists_thesis

ROOT = Path(__file__).resolve().parents[1]


def _wrenches() -> np.ndarray:
    # six directions with stds 1, 0.3, 0.1, 1e-3, 1e-5, 1e-8 about the origin
    rng = np.random.default_rng(0)
    return rng.standard_normal((4000, 6)) * np.array([1, 0.3, 0.1, 1e-3, 1e-5, 1e-8])


def test_override_reaches_a_default_argument_and_is_undone_after_the_block():
    w = _wrenches()
    assert pca_subspace(w).dim == 5  # default subspace_rtol = 1e-6 keeps all but the 1e-8 axis
    with config.override(subspace_rtol=0.05):
        assert config.TOL.subspace_rtol == 0.05 and pca_subspace(w).dim == 3
    assert config.TOL.subspace_rtol == 1e-6 and pca_subspace(w).dim == 5
    with pytest.raises(RuntimeError), config.override(subspace_rtol=0.5):
        raise RuntimeError("a failing block restores them too")
    assert pca_subspace(w).dim == 5


def test_override_of_a_default_changes_the_samplers_and_configure_lasts(monkeypatch):
    a = sample_twists_thesis(20, 0.01)
    with config.override(seed=123):
        b = sample_twists_thesis(20, 0.01)
    assert not np.array_equal(a, b) and np.array_equal(sample_twists_thesis(20, 0.01, 123), b)
    monkeypatch.setattr(config, "DEFAULTS", config.DEFAULTS)  # undone after the test
    config.configure(twist_radius_factor=0.5)
    assert config.DEFAULTS.twist_radius_factor == 0.5
    assert np.array_equal(sample_twists_thesis(20, 0.01), sample_twists_thesis(20, 0.01, radius_factor=0.5))


def test_unknown_names_are_refused_with_the_names_to_use():
    with pytest.raises(ValueError, match=r"unknown tolerance/default/run-setting names \['no_such_rtol'\]"):
        config.configure(no_such_rtol=1.0)
    with pytest.raises(ValueError, match=r"did you mean 'cluster_min_rows' for 'cluster_min_row'\?"):
        config.configure(cluster_min_row=3)
    with pytest.raises(ValueError, match="unknown"), config.override(resist_rtol=1e-9, nope=2):
        pass
    assert config.TOL.resist_rtol != 1e-9


def _library_files() -> list[Path]:
    return [f for f in (ROOT / "workbench").rglob("*.py")]


def test_no_library_module_binds_a_tolerance_or_default_at_import():
    bound = []
    for f in _library_files():
        tree = ast.parse(f.read_text())
        for node in tree.body:  # module-level name imports freeze the object a test may replace
            if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("config"):
                bound += [f"{f.name}: import {a.name}" for a in node.names if a.name in ("TOL", "DEFAULTS")]
        for node in ast.walk(tree):  # default arguments are evaluated once, at import
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                args = node.args
                for d in [*args.defaults, *args.kw_defaults]:
                    if d is not None and any(
                        isinstance(n, ast.Name) and n.id in ("TOL", "DEFAULTS") for n in ast.walk(d)
                    ):
                        bound.append(f"{f.name}:{node.lineno} {node.name}")
    assert len(_library_files()) > 60
    assert bound == []


def test_every_field_has_a_rule_and_every_default_passes_it():
    owners = (config.Tolerances, config.Defaults, config.RunSettings)
    names = [f.name for cls in owners for f in fields(cls)]
    assert sorted(names) == sorted(config._RULES) and len(names) == len(set(names))
    for cls, obj in zip(owners, (config.TOL, config.DEFAULTS, config.RUN), strict=True):
        for f in fields(cls):
            assert config.check_value(f.name, getattr(obj, f.name)) == getattr(obj, f.name), f.name


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"normal_unit_atol": "1e-4"}, r"normal_unit_atol must be a finite number >= 0; got '1e-4' \(str\)"),
        ({"normal_unit_atol": -1.0}, r"normal_unit_atol must be a finite number >= 0; got -1.0"),
        ({"resist_rtol": float("nan")}, r"resist_rtol must be a finite number > 0 and <= 0.1; got nan"),
        ({"resist_rtol": 0.0}, r"resist_rtol must be a finite number > 0 and <= 0.1; got 0.0"),
        ({"max_cut_rounds": 2.5}, r"max_cut_rounds must be an int >= 0; got 2.5 \(float\)"),
        ({"quadrature_max_cells": True}, r"quadrature_max_cells must be an int >= 1; got True \(bool\)"),
        ({"quadrature_rtol": None}, r"quadrature_rtol must be a finite number > 0; got None \(NoneType\)"),
        ({"work_eps": True}, r"work_eps must be a finite number > 0; got True \(bool\)"),
        ({"qp_solver": "nonesuch"}, r"qp_solver must be one of \['auto', .*'quadprog'.*\]; got 'nonesuch'"),
        ({"qp_fallback_solver": "auto"}, r"qp_fallback_solver must be one of \['clarabel'.*got 'auto'"),
        ({"ls_training_sampler": "grid"}, r"must be one of \['thesis', '6dfc', 'thesis-code', 'mix'\]"),
        ({"known_force_rtol": 2.0}, r"known_force_rtol must be a finite number >= 0 and < 1; got 2.0"),
        (
            {"pitch_range": (1.0, -1.0)},
            r"pitch_range must be a tuple of 2 .* with lo <= hi; got \(1.0, -1.0\)",
        ),
        ({"lp_presolve": 1}, r"lp_presolve must be True or False; got 1 \(int\)"),
        ({"cluster_worker_saturation": 0.5}, r"cluster_worker_saturation must be a number >= 1 .*math.inf"),
        ({"cluster_worker_saturation": float("nan")}, r"cluster_worker_saturation must be a number >= 1"),
    ],
)
def test_a_value_its_field_does_not_accept_is_refused_at_set_time(values, message):
    before = config.TOL, config.DEFAULTS
    with pytest.raises(ValueError, match=message + r".*Pass such a value, e\.g\. its default"):
        config.configure(**values)
    with pytest.raises(ValueError, match=message), config.override(subspace_rtol=0.5, **values):
        pass
    assert (config.TOL, config.DEFAULTS) == before  # nothing half-applied


def test_an_int_for_a_float_field_is_stored_as_that_float():
    with config.override(cut_rtol=1, pitch_range=[-2, 2]):
        assert config.TOL.cut_rtol == 1.0 and isinstance(config.TOL.cut_rtol, float)
        assert config.DEFAULTS.pitch_range == (-2.0, 2.0)


def test_run_settings_reach_workers_but_not_the_keys_of_results(tmp_path):
    # a run setting (how a run executes) travels with the tasks like a tolerance, but a checkpoint
    # keys its rows by the numerics alone: rows computed on another cluster size are the same rows
    from workbench.runner.results import Checkpoint

    assert config.RUN.cluster_min_rows == config.RunSettings.cluster_min_rows
    with pytest.raises(AttributeError):
        config.DEFAULTS.cluster_min_rows  # noqa: B018 - the run settings left the numerics
    key = Checkpoint._config_hash({"n": 1}, "code")
    with config.override(cluster_min_rows=3, progress_delay_s=0.0):
        assert config.RUN.cluster_min_rows == 3
        assert config.changed() == {"cluster_min_rows": 3, "progress_delay_s": 0.0}
        assert config.changed(numbers_only=True) == {}
        assert Checkpoint._config_hash({"n": 1}, "code") == key
        with config.override(resist_rtol=1e-6):
            assert config.changed(numbers_only=True) == {"resist_rtol": 1e-6}
            assert Checkpoint._config_hash({"n": 1}, "code") != key
    assert config.RUN.cluster_min_rows == config.RunSettings.cluster_min_rows
    with pytest.raises(ValueError, match=r"cluster_min_rows must be an int >= 0; got -1"):
        config.configure(cluster_min_rows=-1)
