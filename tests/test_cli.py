"""``workbench`` CLI: a bad --set value stops ``workbench run`` with status 2 before any
work, ``run NAME --help`` lists the keys, and the option order is free.  No experiment runs
here: bad values stop before ``run``, and the good-path tests replace ``run``.  The config
checks themselves (build_config) are tested in test_experiment_config.py."""

import importlib
import json

import pytest

from workbench.cli import main
from workbench.experiment_config import EXPERIMENTS


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
