"""``workbench`` CLI: a bad --set value stops ``workbench run`` with status 2 before any
work, ``run NAME --help`` lists the keys, and the option order is free.  No experiment runs
here: bad values stop before ``run``, and the good-path tests replace ``run``.  The config
checks themselves (build_config) are tested in test_experiment_config.py."""

import importlib
import json

import pytest

from workbench.runner.cli import main
from workbench.runner.experiment_config import EXPERIMENTS


def _error(capsys, argv):
    """Run ``main(argv)``; it must exit with status 2 and an error on stderr."""
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    return capsys.readouterr().err


def test_non_int_value_names_key_type_and_value(capsys):
    err = _error(capsys, ["run", "parametric-surfaces", "--set", "n_pca=abc"])
    assert "n_pca=abc" in err and "n_pca expects int (default 1000)" in err and "'abc' is not an int" in err


def test_quick_is_not_a_set_value(capsys):
    """``--set quick=true`` marked a config quick without its quick values; --quick does both."""
    err = _error(capsys, ["run", "discretization", "--set", "quick=maybe"])
    assert "['quick'] are set by --quick and --out, not as config values" in err


def test_experiment_help_lists_keys_types_and_defaults(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "sensitivity", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    module = importlib.import_module(EXPERIMENTS["sensitivity"])
    for key, default in module.DEFAULT_CONFIG.items():
        assert f"  {key} (" in out and json.dumps(default) in out, key
    assert "half_angle (float) = 0.6" in out
    assert 'models (list of str) = ["point",' in out
    assert "n_elements (int) = 300   [--quick: 150]" in out


def test_run_help_lists_every_experiment(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    out = capsys.readouterr().out
    for name in EXPERIMENTS:
        assert f"  {name} " in out, name


def test_list_and_option_order_unchanged(capsys, monkeypatch, tmp_path):
    assert main(["list"]) == 0
    assert capsys.readouterr().out.splitlines()[0].startswith("parametric-surfaces")
    seen = {}
    module = importlib.import_module(EXPERIMENTS["discretization"])

    def fake_run(config):
        seen.update(config)
        return {"headline": ["fake"]}

    monkeypatch.setattr(module, "run", fake_run)
    argv = ["run", "--set", "timing_repeats=2", "discretization", "--quick", "--out", str(tmp_path)]
    assert main([*argv, "--seed", "4", "--set", "mu=0.5"]) == 0
    assert seen["quick"] is True and seen["out"] == str(tmp_path) and seen["seed"] == 4
    assert seen["timing_repeats"] == 2 and seen["mu"] == 0.5
    assert seen["n_elements"] == module.QUICK_CONFIG["n_elements"]


def test_run_says_how_many_rows_it_resumed(capsys, monkeypatch, tmp_path):
    """A re-run that read every row back said nothing of it (a new-user trial): its headline's
    timings looked measured in that run."""
    module = importlib.import_module(EXPERIMENTS["sensitivity"])
    for resumed, said in ((41, " (41 rows resumed from its checkpoint)"), (0, "")):
        monkeypatch.setattr(module, "run", lambda config, n=resumed: {"n_resumed": n, "headline": ["h"]})
        assert main(["run", "sensitivity", "--quick", "--out", str(tmp_path)]) == 0
        first = capsys.readouterr().out.splitlines()[0]
        assert first.startswith(f"sensitivity: wrote {tmp_path}/summary.json in ")
        assert first.endswith(f" s{said}")


def test_seed_is_refused_for_an_experiment_without_a_seed_key(capsys, monkeypatch, tmp_path):
    """``--seed 5`` on sensitivity-engine (whose grasps come from its ``seeds`` list) ran the
    seed-0 trials while summary.json recorded seed 5; ``--seed -3`` passed too.  Both are refused
    before ``run``, naming the experiment's own seed key and a pasteable --set."""
    ran = []
    for name in ("sensitivity-engine", "engine-validation"):
        monkeypatch.setattr(importlib.import_module(EXPERIMENTS[name]), "run", ran.append)
    out = tmp_path / "out"
    for seed, given in (("5", "[5]"), ("-3", "[0]")):  # a negative seed is not suggested back
        err = _error(capsys, ["run", "sensitivity-engine", "--quick", "--out", str(out), "--seed", seed])
        assert f"error: --seed {seed}: sensitivity-engine has no `seed` key" in err, err
        assert "`seeds` (seeds of the disturbances and noise, one set of grasps each; a list)" in err
        assert err.rstrip().endswith(f"use --set 'seeds={given}'"), err
    err = _error(capsys, ["run", "engine-validation", "--quick", "--seed", "5"])
    assert "engine-validation has no `seed` key" in err and "it takes no seed — drop --seed" in err
    assert ran == [] and not out.exists()


def test_sweep_refuses_a_seed_the_experiment_does_not_read(capsys, tmp_path):
    out = tmp_path / "sweep"
    argv = ["sweep", "sensitivity-engine", "--quick", "--grid", "n_disturbances=[2,3]", "--seed", "5"]
    err = _error(capsys, [*argv, "--out", str(out)])
    assert err.startswith("workbench sweep sensitivity-engine: error: --seed 5: sensitivity-engine has no")
    assert "use --set 'seeds=[5]'" in err and "point" not in err  # the option, not a grid point
    assert not out.exists()


def test_config_settings_hold_for_the_run_and_are_refused_when_careless(capsys, monkeypatch, tmp_path):
    """``--config NAME=VALUE`` sets a workbench.config tolerance or default for the run alone (a
    researcher running the grasp dataset on a coarsened training contact); a careless one stops
    the run with status 2 before any work, naming the field."""
    from workbench import config

    module = importlib.import_module(EXPERIMENTS["discretization"])
    seen = []
    monkeypatch.setattr(
        module,
        "run",
        lambda cfg: (
            seen.append((config.DEFAULTS.ls_training_cell_fraction, config.DEFAULTS.ls_training_sampler))
            or {"headline": []}
        ),
    )
    argv = [
        "run",
        "discretization",
        "--quick",
        "--out",
        str(tmp_path),
        "--config",
        "ls_training_cell_fraction=0.1",
    ]
    assert main([*argv, "--config", "ls_training_sampler=thesis"]) == 0
    assert seen == [(0.1, "thesis")]
    assert config.DEFAULTS.ls_training_cell_fraction == 0.0  # restored after the run
    for bad, said in (
        ("ls_training_cell_fraction=3", "not millimetres or metres"),
        ("ls_training_cell=0.1", "did you mean 'ls_training_cell_fraction'"),
        ("ls_training_sampler", "expects NAME=VALUE"),
    ):
        err = _error(capsys, ["run", "discretization", "--quick", "--config", bad])
        assert "workbench run discretization: error: --config:" in err and said in err, err
    err = _error(capsys, [*argv, "--config", "ls_training_cell_fraction=0.2"])
    assert "ls_training_cell_fraction is given twice" in err
    assert len(seen) == 1


def test_summary_records_the_settings_away_from_their_defaults(tmp_path):
    from workbench import config
    from workbench.runner.results import write_summary

    assert "settings" not in write_summary(tmp_path, "x", {}, {}, 0.0)
    with config.override(ls_training_cell_fraction=0.15, cluster_min_rows=5):
        full = write_summary(tmp_path, "x", {}, {}, 0.0)
    # the run settings (how a run executes) change no number and are not recorded as its settings
    assert full["settings"] == {"ls_training_cell_fraction": 0.15}
    assert json.loads((tmp_path / "summary.json").read_text())["settings"] == full["settings"]


def test_sweep_config_settings_hold_for_every_point_and_are_refused_when_careless(
    capsys, monkeypatch, tmp_path
):
    from workbench import config
    from workbench.runner import sweep

    seen = []

    def fake_sweep(*a, **k):
        seen.append(config.DEFAULTS.ls_training_cell_fraction)
        return {"n_failed": 0, "table": [], "n_points": 0}

    monkeypatch.setattr(sweep, "run_sweep", fake_sweep)
    monkeypatch.setattr("workbench.runner.cli._print_sweep", lambda *a: None)
    base = ["sweep", "discretization", "--grid", "mu=[0.3]", "--out", str(tmp_path)]
    assert main([*base, "--config", "ls_training_cell_fraction=0.2"]) == 0
    assert seen == [0.2] and config.DEFAULTS.ls_training_cell_fraction == 0.0
    err = _error(capsys, [*base, "--config", "ls_training_cell_fraction=-1"])
    assert "workbench sweep discretization: error: --config:" in err and "not millimetres or metres" in err
    assert seen == [0.2]
