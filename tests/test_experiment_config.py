"""workbench.runner.experiment_config: each run's config from the experiment's defaults, its quick
overrides and the user's ``--set`` values — coerced to the defaults' types, ranges read off
the defaults, unknown keys and an experiment's own checks refused before any work — and
``config_help``'s listing (the real experiments, and a toy one with known defaults)."""

import importlib
import re
import shlex

import pytest
import sweep_toy

from workbench.runner.experiment_config import (
    EXPERIMENTS,
    _parse_sets,
    build_config,
    config_help,
    seed_refusal,
)


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
        # JSON that does not parse says so (a new-user trial got only "is not a list")
        ('figure_surfaces=["S1"', "'[\"S1\"' is not a JSON list (Expecting ',' delimiter"),
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
    sets = _parse_sets(["mu=1", "deltas_mm=[1, 2.5]", "scheduler=5", "n_objects=3"])
    cfg = build_config("fem-fitting", False, None, None, sets)
    assert cfg["mu"] == 1.0 and isinstance(cfg["mu"], float)  # an int is accepted for a float
    assert cfg["deltas_mm"] == [1.0, 2.5] and all(isinstance(d, float) for d in cfg["deltas_mm"])
    assert cfg["scheduler"] == "5"  # a str key keeps the text, not the JSON number
    assert cfg["n_objects"] == 3 and cfg["quick"] is False
    # Python callers pass typed values: checked the same way
    with pytest.raises(SystemExit, match="5 is not a string"):
        build_config("fem-fitting", False, None, None, {"scheduler": 5})


def test_unknown_keys_still_rejected():
    with pytest.raises(SystemExit, match=r"unknown config keys for discretization: \['nope'\]; known"):
        build_config("discretization", False, None, None, _parse_sets(["nope=1"]))
    # a near miss is named
    with pytest.raises(SystemExit, match=r"\['muu'\] \(did you mean 'mu' for 'muu'\?\)"):
        build_config("parametric-surfaces", False, None, None, _parse_sets(["muu=1"]))


@pytest.mark.parametrize("key", ["quick", "out"])
def test_quick_and_out_are_not_config_values(key):
    """``--set quick=true`` used to mark a config quick without its quick values (a sweep row
    labelled quick=False ran quick); ``out`` in a sweep's grid wrote outside the sweep."""
    with pytest.raises(SystemExit, match=rf"\['{key}'\] are set by --quick and --out"):
        build_config("parametric-surfaces", False, None, None, {key: "x"})


def test_a_key_set_twice_is_refused():
    with pytest.raises(SystemExit, match="--set mu is given twice \\(1 and 2\\); give it once"):
        _parse_sets(["mu=1", "mu=2"])


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
    if "thesis_dir" in module.DEFAULT_CONFIG:  # grasp-dataset's meshes may be absent too
        (tmp_path / "box.obj").touch()
        sets["meshes"] = str(tmp_path / "*.obj")
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


def test_seed_flag_is_checked_like_a_set_seed():
    """``--seed -1`` passed the checks and failed in numpy at the first random draw (``--set
    seed=-1`` and a sweep's ``--grid seed=[-1]`` were refused up front)."""
    with pytest.raises(SystemExit, match=r"--seed -1: seed expects int .* negative .* give e.g. --seed 0"):
        build_config("sensitivity", True, None, -1, {})
    with pytest.raises(SystemExit, match="--seed 2.5: seed expects int"):
        build_config("discretization", True, None, 2.5, {})
    assert build_config("sensitivity", True, None, 3, {})["seed"] == 3


def test_cli_config_layers():
    cfg = build_config("discretization", True, None, 7, {"timing_repeats": 2})
    assert cfg["seed"] == 7 and cfg["timing_repeats"] == 2 and cfg["quick"]
    assert cfg["out"].endswith("results/discretization")
    with pytest.raises(SystemExit, match="unknown config keys"):
        build_config("discretization", False, None, None, {"nope": 1})


# --- added: a toy experiment whose defaults are known here ----------------------------------


@pytest.fixture
def toy(monkeypatch):
    """tests/sweep_toy.py registered as "toy": DEFAULT_CONFIG {"seed": 0, "x": 1.0,
    "fail_above": 10.0, "sleep": 0.0, "tag": "a", "shape": [1, 2]}, QUICK_CONFIG {"sleep": 0.0}."""
    monkeypatch.setitem(EXPERIMENTS, "toy", "sweep_toy")
    return sweep_toy


def test_toy_config_layers_and_coercion(toy, tmp_path):
    cfg = build_config("toy", False, str(tmp_path), 5, _parse_sets(["x=2", "tag=S3", "shape=[3, 4]"]))
    assert cfg == {
        "seed": 5,
        "x": 2.0,
        "fail_above": 10.0,
        "sleep": 0.0,
        "tag": "S3",
        "shape": [3, 4],
        "quick": False,
        "out": str(tmp_path),
    }
    assert isinstance(cfg["x"], float) and isinstance(cfg["seed"], int)
    assert build_config("toy", True, None, None, {})["out"] == "results/toy"
    assert build_config("toy", False, None, None, _parse_sets(['tag="7"']))["tag"] == "7"  # a JSON string
    for item, msg in [
        ("shape=[3, 4.5]", r"shape expects list of int \(default \[1, 2\]\); element 1: 4.5 is not an int"),
        ("x=-1", r"x=-1: x expects float \(default 1.0\); -1.0 is negative"),  # a default >= 0: no negatives
        ("seed=1e3", "1000.0 is not an int"),
        ("fail_above=[1]", r"\[1\] is not a number"),
    ]:
        with pytest.raises(SystemExit, match=msg):
            build_config("toy", False, None, None, _parse_sets([item]))
    with pytest.raises(SystemExit, match=r"--set expects key=value; got 'x'"):
        _parse_sets(["x"])
    with pytest.raises(SystemExit, match=r"unknown experiment 'nope'; known: \["):
        build_config("nope", False, None, None, {})


def test_an_experiments_own_check_becomes_a_clean_exit(toy, monkeypatch):
    def check_config(config):
        if config["x"] > config["fail_above"]:
            raise ValueError(f"x must be <= fail_above; got {config['x']}")

    monkeypatch.setattr(toy, "check_config", check_config, raising=False)
    assert build_config("toy", False, None, None, {"x": 3.0})["x"] == 3.0
    with pytest.raises(SystemExit, match=r"^toy: x must be <= fail_above; got 11.0$"):
        build_config("toy", False, None, None, {"x": 11.0})


def test_config_help_lists_types_defaults_and_quick_values(toy):
    assert config_help("toy").splitlines() == [
        "config keys (--set KEY=VALUE, JSON; a bare word is a string):",
        "  seed (int) = 0",
        "      random seed (numpy), >= 0",  # experiment_keys.COMMON: the toy declares no KEYS
        "  x (float) = 1.0",
        "  fail_above (float) = 10.0",
        "  sleep (float) = 0.0   [--quick: 0.0]",
        '  tag (str) = "a"',
        "  shape (list of int) = [1, 2]",
        "  quick, out: set by --quick and --out",
    ]


@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_config_help_has_one_line_per_default_key(name):
    """Each key's line (type, default, --quick value), then what it means (its Key, described)."""
    module = importlib.import_module(EXPERIMENTS[name])
    lines = config_help(name).splitlines()
    assert len(lines) == 2 * len(module.DEFAULT_CONFIG) + 2  # every key has a Key (test_experiment_keys)
    for i, key in enumerate(module.DEFAULT_CONFIG):
        assert lines[1 + 2 * i].startswith(f"  {key} (")
        assert lines[2 + 2 * i].startswith("      ") and len(lines[2 + 2 * i].strip()) > 10


@pytest.mark.parametrize(
    "name, sets, match",
    [
        (
            "parametric-surfaces",
            {"figure_surfaces": ["S1", "S9"]},
            r"figure_surfaces must be one of \['S1', .*'S6'\]; got \['S1', 'S9'\]",
        ),
        ("parametric-surfaces", {"example_mu": 0.0}, "mu = 0 has no friction wrench"),
        ("ls-fitting", {"surfaces": ["S9"]}, r"surfaces must be one of \['S1'.*got \['S9'\]"),
        ("ls-fitting", {"section_surface": "s4"}, r"section_surface must be one of \['S1'.*got 's4'"),
        ("ls-fitting", {"surfaces": []}, "at least one"),
        ("ls-fitting", {"surfaces": ["S1", "S1"]}, "each once"),
        ("discretization", {"timing_twists": 0}, "timing_twists must be >= 1"),
        ("discretization", {"n_elements": [1]}, "n_elements must be mesh sizes >= 2"),
        ("discretization", {"timing_rtol": 0.0}, "timing_rtol must be a relative tolerance > 0"),
        ("discretization", {"timing_repeats": 0}, "timing_repeats must be >= 1"),
    ],
)
def test_surface_names_are_checked_before_any_work(name, sets, match):
    """An unknown surface used to fail mid-run with a bare KeyError (a sweep point after 3.7 s)."""
    with pytest.raises(SystemExit, match=match):
        build_config(name, True, None, None, sets)


def test_seed_given_twice_is_refused():
    with pytest.raises(SystemExit, match=r"seed is given by --seed \(3\) and by --set seed=4: give it once"):
        build_config("discretization", True, None, 3, {"seed": 4})


def test_a_bad_value_carries_its_parts_for_another_option():
    """The CLI's message and the parts a sweep words for --grid come from one error."""
    from workbench.runner.experiment_config import ConfigValueError

    with pytest.raises(ConfigValueError) as exc:
        build_config("discretization", False, None, None, {"mu": -1})
    e = exc.value
    assert isinstance(e, SystemExit)  # the CLI prints it as before
    assert (e.key, e.text, e.expects, e.default, e.flag) == ("mu", "-1", "float", "1.0", "--set")
    assert "negative" in e.reason
    assert str(e.code) == e.message()
    assert e.message().startswith("--set mu=-1: mu expects float (default 1.0)")
    assert e.message("grid value mu=-1", "fix it").endswith(f"{e.reason} — fix it")
    with pytest.raises(ConfigValueError) as exc:
        build_config("discretization", False, None, -1, {})
    assert exc.value.flag == "--seed" and exc.value.example() == "--seed 0"


@pytest.mark.parametrize(
    "name, own",
    [
        ("sensitivity-engine", {"seeds": [5]}),
        ("sensitivity-engine-bottles", {"seeds": [5], "family_seed": 5}),
        ("engine-validation", {}),
    ],
)
def test_seed_flag_is_refused_where_no_seed_key_reads_it(name, own):
    """An experiment without a ``seed`` key ran unchanged under ``--seed 5`` and recorded it; now
    the refusal names each of its own seed keys with a --set that build_config takes as given."""
    with pytest.raises(SystemExit) as exc:
        build_config(name, True, None, 5, {})
    msg = str(exc.value.code)
    assert msg.startswith(f"--seed 5: {name} has no `seed` key"), msg
    assert seed_refusal(name, 5) == msg
    pasted = [shlex.split(arg)[0] for arg in re.findall(r"--set ('[^']*'|\S+)", msg)]
    assert {arg.split("=")[0] for arg in pasted} == set(own), msg
    cfg = build_config(name, True, None, None, _parse_sets(pasted))
    assert {k: cfg[k] for k in own} == own


@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_every_experiment_with_a_seed_key_takes_the_seed_flag(name):
    module = importlib.import_module(EXPERIMENTS[name])
    assert (seed_refusal(name, 5) is None) == ("seed" in module.DEFAULT_CONFIG)
