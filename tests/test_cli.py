"""``workbench`` CLI: --set values are checked against each experiment's defaults
before any work, and ``run NAME --help`` lists the keys.  No experiment runs here:
bad values stop before ``run``, and the good-path tests replace ``run``."""

import importlib
import json

import pytest

from workbench.cli import main
from workbench.experiment_config import EXPERIMENTS, _parse_sets, build_config


def _error(capsys, argv):
    """Run ``main(argv)``; it must exit with status 2 and an error on stderr."""
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    return capsys.readouterr().err


def test_non_int_value_names_key_type_and_value(capsys):
    err = _error(capsys, ["run", "parametric-surfaces", "--set", "n_pca=abc"])
    assert "n_pca=abc" in err and "n_pca expects int (default 1000)" in err and "'abc' is not an int" in err


def test_non_bool_quick_is_rejected(capsys):
    err = _error(capsys, ["run", "discretization", "--set", "quick=maybe"])
    assert "quick expects bool (default false)" in err and "'maybe' is not a bool (true or false)" in err


@pytest.mark.parametrize(
    "item, expect",
    [
        ("n_pca=12.5", "12.5 is not an int"),
        ("n_pca=true", "True is not an int"),  # JSON true is not a count
        ("mu=NaN", "nan is not finite"),
        ("mu=Infinity", "inf is not finite"),
        ("mu=fast", "'fast' is not a number"),
        ("figure_surfaces=S1", "figure_surfaces expects list of str"),
        ('figure_surfaces=["S1", 2]', "element 1: 2 is not a string"),
    ],
)
def test_bad_values_are_rejected_before_any_work(item, expect):
    with pytest.raises(SystemExit) as exc:
        build_config("parametric-surfaces", False, None, None, _parse_sets([item]))
    assert expect in str(exc.value.code)


def test_nested_dict_values_are_checked():
    # a dict of one value type takes free keys; a dict of mixed types is a record with fixed keys
    cfg = build_config("fem-fitting", True, None, None, _parse_sets(['approaches={"diag": 1}']))
    assert cfg["approaches"] == {"diag": 1.0} and isinstance(cfg["approaches"]["diag"], float)
    with pytest.raises(SystemExit, match=r"\['nx'\]: 2.5 is not an int"):
        build_config("fem-fitting", True, None, None, _parse_sets(['pad={"nx": 2.5}']))
    with pytest.raises(SystemExit, match=r"unknown key\(s\) \['depth'\]"):
        build_config("fem-fitting", True, None, None, _parse_sets(['pad={"depth": 0.01}']))
    with pytest.raises(SystemExit, match="element 0: element 1: 'a' is not an int"):
        build_config("wall-stiffness", False, None, None, _parse_sets(['convergence_meshes=[[32, "a"]]']))


def test_good_values_are_coerced_to_the_default_types():
    sets = _parse_sets(["mu=1", "deltas_mm=[1, 2.5]", "scheduler=5", "n_objects=3", "quick=true"])
    cfg = build_config("fem-fitting", False, None, None, sets)
    assert cfg["mu"] == 1.0 and isinstance(cfg["mu"], float)  # an int is accepted for a float
    assert cfg["deltas_mm"] == [1.0, 2.5] and all(isinstance(d, float) for d in cfg["deltas_mm"])
    assert cfg["scheduler"] == "5"  # a str key keeps the text, not the JSON number
    assert cfg["n_objects"] == 3 and cfg["quick"] is True
    # Python callers pass typed values: checked the same way
    with pytest.raises(SystemExit, match="5 is not a string"):
        build_config("fem-fitting", False, None, None, {"scheduler": 5})


def test_unknown_keys_still_rejected():
    with pytest.raises(SystemExit, match=r"unknown config keys for discretization: \['nope'\]"):
        build_config("discretization", False, None, None, _parse_sets(["nope=1"]))


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


@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_quick_overrides_fit_the_default_types(name, tmp_path):
    # --quick values go through the same check, so a QUICK_CONFIG that contradicts its
    # DEFAULT_CONFIG type (a typo'd key, a str for a list) fails here, not mid-run
    module = importlib.import_module(EXPERIMENTS[name])
    sets = dict(module.QUICK_CONFIG)
    if "data_dir" in module.DEFAULT_CONFIG:  # the CC BY-NC data may be absent: stand-in files
        for obj in module.DEFAULT_CONFIG.get("objects", [module.DEFAULT_CONFIG.get("object")]):
            for sub, ext in (("meshes", "obj"), ("stiffness_maps", "json")):
                (tmp_path / sub).mkdir(exist_ok=True)
                (tmp_path / sub / f"{obj}.{ext}").touch()
        sets["data_dir"] = str(tmp_path)
    cfg = build_config(name, False, None, None, sets)
    assert {k: cfg[k] for k in module.QUICK_CONFIG} == module.QUICK_CONFIG


@pytest.mark.parametrize(
    "item, words",
    [
        ("mu=-1", ["mu", "negative", "default 0.3"]),
        ("force_range=[1]", ["force_range", "[lo, hi]"]),
        ("force_range=[35, 20]", ["force_range", "lo <= hi"]),
        ("noise_mu=-0.1", ["noise_mu", "negative"]),
        ("k_values=[2, -1]", ["k_values", "[-1.0]", "negative"]),
    ],
)
def test_ranges_read_off_the_defaults_are_checked_before_any_work(item, words):
    """Seen in a new-user trial: these started the sensitivity run and failed deep inside
    (or, noise_mu=-0.1, ran on and wrote rows)."""
    with pytest.raises(SystemExit) as exc:
        build_config("sensitivity", False, None, None, _parse_sets([item]))
    assert all(w in str(exc.value) for w in words), str(exc.value)


def test_offsets_with_negative_defaults_stay_free():
    cfg = build_config("sensitivity", False, None, None, _parse_sets(["mu_offsets=[-0.3, 0.3]"]))
    assert cfg["mu_offsets"] == [-0.3, 0.3]


def test_the_suggested_value_is_shell_quoted():
    """The hint must work when pasted: a list with spaces and brackets is quoted."""
    import shlex

    with pytest.raises(SystemExit) as exc:
        build_config("fem-fitting", True, None, None, _parse_sets(["heights=0.5"]))
    hint = str(exc.value.code).split("give e.g. ")[1]
    argv = shlex.split(hint)
    assert argv[0] == "--set" and len(argv) == 2
    from workbench.experiments.fem_fitting import DEFAULT_CONFIG

    suggested = build_config("fem-fitting", True, None, None, _parse_sets([argv[1]]))["heights"]
    assert suggested == DEFAULT_CONFIG["heights"] and len(suggested) == 21  # the default, pasted back
