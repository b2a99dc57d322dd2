"""Every experiment's config keys described and judged: each ``DEFAULT_CONFIG`` key has
a :class:`~workbench.runner.experiment_keys.Key` (its module's ``KEYS`` or the shared ``COMMON``), the
defaults and ``--quick`` values pass their own keys silently, ``workbench run NAME --help`` shows
units, plausible ranges and allowed words, and careless ``--set`` / ``--grid`` values are refused
before any work with the likely unit slip named (or warned when only unusual)."""

import importlib
import warnings

import pytest

from workbench.plausible import RANGES, ImplausibleWarning
from workbench.runner import cli
from workbench.runner.experiment_config import EXPERIMENTS, build_config, config_help, key_specs
from workbench.runner.experiment_keys import COMMON, check_key, describe

NAMES = sorted(EXPERIMENTS)


def _module(name: str):
    return importlib.import_module(EXPERIMENTS[name])


def _help_lines(name: str) -> dict[str, str]:
    """key -> the description line under it in ``config_help(name)``."""
    lines = config_help(name).splitlines()
    out = {}
    for head, desc in zip(lines[1:], lines[2:], strict=False):
        if head.startswith("  ") and not head.startswith("   ") and desc.startswith("      "):
            out[head.split()[0]] = desc.strip()
    return out


# ---------------------------------------------------------------- (1) one Key per key


@pytest.mark.parametrize("name", NAMES)
def test_every_default_key_has_a_key_and_every_key_names_a_default(name):
    module = _module(name)
    own = getattr(module, "KEYS", None)
    assert isinstance(own, dict) and own, f"{name} declares no KEYS"
    keys = key_specs(module)
    assert [k for k in module.DEFAULT_CONFIG if k not in keys] == []
    assert [k for k in own if k not in module.DEFAULT_CONFIG] == []
    assert [k for k in COMMON if k in own] == []  # seed, workers, scheduler mean the same everywhere


#: keys that are a physical input wherever they appear; physical-trials' mass has none: its 0
#: means "read by the object's name", which the mass range refuses (judged in check_config)
PHYSICAL = {"E", "nu", "mu", "thickness", "force", "force_stop", "grasp_force", "force_cap", "jaw", "mass_kg"}


@pytest.mark.parametrize("name", NAMES)
def test_physical_keys_carry_their_quantity(name):
    module = _module(name)
    keys = key_specs(module)
    bare = [k for k in module.DEFAULT_CONFIG if k in PHYSICAL and keys[k].quantity is None]
    assert bare == []


@pytest.mark.parametrize(
    "name, key, quantity, scale",
    [
        ("fem-fitting", "E", "pad_modulus", 1.0),  # the silicone pad's
        ("peers", "E", "pad_modulus", 1.0),
        ("minimal-work", "E", "wall_modulus", 1.0),  # the object's wall
        ("wall-nonlinear", "E", "wall_modulus", 1.0),
        ("fem-fitting", "mu", "mu", 1.0),  # normalised away, still a friction coefficient
        ("fem-fitting", "deltas_mm", "compression", 1e-3),
        ("minimal-work", "mass_kg", "mass", 1.0),
        ("sensitivity", "force_range", "jaw_force", 1.0),
        ("fem-validation", "winkler_h", "pad_thickness", 1.0),
        ("physical-trials", "mass", "mass", 1.0),  # 0 (unset) reads REACH's mass
    ],
)
def test_a_key_is_the_quantity_it_really_is(name, key, quantity, scale):
    spec = key_specs(_module(name))[key]
    assert (spec.quantity, spec.scale) == (quantity, scale)


def test_pad_dicts_judge_their_sizes_by_field():
    spec = key_specs(_module("fem-fitting"))["pad"]
    assert spec.fields == {
        "width": ("pad_size", 1.0),
        "length": ("pad_size", 1.0),
        "thickness": ("pad_thickness", 1.0),
    }
    # a pad given as a list [w, l, h] in mm: two sizes and a thickness by position
    assert key_specs(_module("peers"))["pad_mm"].fields == {
        0: ("pad_size", 1e-3),
        1: ("pad_size", 1e-3),
        2: ("pad_thickness", 1e-3),
    }


# ---------------------------------------------------------------- (2) defaults pass silently


@pytest.mark.parametrize("name", NAMES)
def test_default_and_quick_values_pass_their_own_keys_without_a_warning(name):
    module = _module(name)
    keys = key_specs(module)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        for values in (module.DEFAULT_CONFIG, module.QUICK_CONFIG):
            for key, value in values.items():
                check_key(key, keys[key], value)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("quick", [False, True])
def test_default_configs_pass_their_experiments_check_config_without_a_warning(name, quick, tmp_path):
    """check_config judges every key by its Key too (run(config) called directly is checked)."""
    module = _module(name)
    config = {**module.DEFAULT_CONFIG, **(module.QUICK_CONFIG if quick else {}), "quick": quick}
    if "data_dir" in config:  # the CC BY-NC data may be absent: stand-in files
        for obj in config.get("objects", [config.get("object")]):
            for sub, ext in (("meshes", "obj"), ("stiffness_maps", "json")):
                (tmp_path / sub).mkdir(exist_ok=True)
                (tmp_path / sub / f"{obj}.{ext}").touch()
        config["data_dir"] = str(tmp_path)
    if "thesis_dir" in config:  # grasp-dataset's meshes may be absent too
        (tmp_path / "box.obj").touch()
        config["meshes"] = str(tmp_path / "*.obj")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleWarning)
        module.check_config(config)


@pytest.mark.parametrize(
    "name, key, value, words",
    [
        ("wall-nonlinear", "thickness", 0.5, ["thickness [m]", "probably in millimetres — pass 0.0005"]),
        ("fem-fitting", "E", 1.0, ["E [Pa]", "probably in MPa — pass 1e+06"]),
        ("peers", "mu", 50.0, ["probably in per cent — pass 0.5"]),
        ("fem-validation", "compare_nu", 49.9, ["probably in per cent — pass 0.499"]),
        ("sensitivity", "force_range", [20e3, 35e3], ["probably in millinewtons — pass 20"]),
        ("physical-trials", "mass", 30.0, ["probably in grams — pass 0.03 [kg]"]),
        # no Key quantity (its default is beyond the usual range on purpose), the Poisson rule still
        ("fem-validation", "thin_film_nu", 49.999, ["thin_film_nu: nu must be a Poisson ratio in (-1, 0.5)"]),
        ("physical-trials", "models", ["6dls", "6dlss"], ["models must be one of ['point'"]),
    ],
)
def test_check_config_alone_refuses_careless_values(name, key, value, words):
    """The same rules when run(config) is called without build_config (a script, a sweep task)."""
    module = _module(name)
    config = {**module.DEFAULT_CONFIG, key: value, "quick": True}
    with pytest.raises(ValueError) as exc:
        module.check_config(config)
    assert all(w in str(exc.value) for w in words), str(exc.value)


# ---------------------------------------------------------------- (3) --help


@pytest.mark.parametrize("name", NAMES)
def test_help_shows_unit_and_range_of_every_physical_key_and_the_words_of_every_choice_key(name):
    keys = key_specs(_module(name))
    shown = _help_lines(name)
    for key, spec in keys.items():
        if key not in _module(name).DEFAULT_CONFIG:
            continue
        line = shown[key]
        assert line == describe(spec)
        if spec.quantity is not None:
            r = RANGES[spec.quantity]
            assert f"plausible {r.interval(spec.scale)} {spec.unit}".rstrip() in line, line
            if r.unit:
                assert f"[{spec.unit}]" in line, line
        if spec.choices is not None:
            assert "one of " + ", ".join(map(str, spec.allowed())) in line, line


@pytest.mark.parametrize(
    "name, key, text",
    [
        ("wall-stiffness", "top", "one of auto, lip, clamped, free"),
        ("wall-stiffness", "E", "wall Young's modulus [Pa]; plausible (100000, 1e+12] Pa"),
        (
            "fem-fitting",
            "E",
            "pad Young's modulus (profiles are normalised: E only scales the force) [Pa]; "
            "plausible (1000, 1e+10] Pa",
        ),
        ("fem-fitting", "nu", "pad Poisson ratio; plausible (-1, 0.5)"),
        ("fem-fitting", "code_frame", "one of object, jaw"),
        ("fem-fitting", "fine_level", "one of -1, 0, 1, 2, 3, 4, 5, 6"),
        ("fem-fitting", "deltas_mm", "[mm]; plausible [0, 20] mm"),
        (
            "peers",
            "pad_mm",
            "[mm]; [0] pad size (0.1, 200] mm; [1] pad size (0.1, 200] mm; [2] pad thickness [0.1, 100] mm",
        ),
        ("peers", "ls_model", "one of ellipsoid_lsq, ellipsoid_sdp, quartic_values, quartic_normals"),
        (
            "sensitivity",
            "models",
            "one of point, soft_point, planar, 3dls_nonplanar, 6dfw, reach, 6dls, 6dls_quartic, 6dfc",
        ),
        ("sensitivity", "training_samplers", "one of thesis, 6dfc, thesis-code, mix"),
        ("sensitivity", "force_range", "[N]; plausible (0, 500] N"),
        ("minimal-work", "profiles", "one of reach, fem"),
        ("minimal-work", "thickness", "wall thickness [m]; plausible [1e-05, 0.05] m"),
        ("minimal-work", "reach_closing_mm", "[mm]; plausible [0, 20] mm"),
        ("ls-fitting", "wrench_source", "one of continuous, mesh"),
        ("ls-fitting", "surfaces", "one of S1, S2, S3, S4, S5, S6"),
        ("parametric-surfaces", "example_mu", "plausible [0, 2]"),
        ("physical-trials", "mass", "[kg]; plausible (0, 20] kg, usual [0.001, 10] kg; 0.0 = not given"),
        ("physical-trials", "mu", "0 = the gripper's own (YuMi: 0.3); plausible [0, 2]"),
        ("fem-validation", "winkler_h", "[m]; plausible [0.0001, 0.1] m"),
        ("wall-nonlinear", "step_mm", "[mm]; plausible [0, 100] mm"),
        ("discretization", "mu", "plausible [0, 2]"),
    ],
)
def test_help_lines_read_as_expected(name, key, text):
    assert text in _help_lines(name)[key]


def test_help_of_a_map_of_masses_gives_the_mass_range():
    line = _help_lines("minimal-work")["mass_kg"]
    assert line.startswith("filled mass of each object, {object: kg} [kg]; plausible (0, ")
    assert line.endswith(" kg")


def test_cli_run_help_lists_the_keys_meaning(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["run", "wall-stiffness", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "object=: top edge of the wall; one of auto, lip, clamped, free" in out
    assert "force per jaw [N]; plausible (0, 500] N" in out


# ---------------------------------------------------------------- (4) careless values


CARELESS = [
    # SI keys: the slip and the value to pass
    ("wall-stiffness", {"E": 2500}, ["--set E=2500.0", "probably in MPa — pass 2.5e+09 [Pa]"]),
    ("wall-stiffness", {"thickness": 0.5}, ["probably in millimetres — pass 0.0005 [m]"]),
    ("wall-stiffness", {"force": 1e4}, ["force [N]", "probably in millinewtons — pass 10 [N]"]),
    ("wall-stiffness", {"jaw": [20, 40]}, ["jaw[0] [m]", "probably in millimetres — pass 0.02 [m]"]),
    ("wall-stiffness", {"nu": 45}, ["Poisson ratio", "probably in per cent — pass 0.45"]),
    ("wall-nonlinear", {"E": 2500}, ["probably in MPa — pass 2.5e+09"]),
    ("wall-nonlinear", {"force_stop": 13000}, ["probably in millinewtons — pass 13 [N]"]),
    ("minimal-work", {"E": 2.5}, ["probably in GPa — pass 2.5e+09"]),
    ("minimal-work", {"thickness": 0.5}, ["probably in millimetres — pass 0.0005"]),
    ("minimal-work", {"grasp_force": 1e4}, ["grasp_force [N]", "probably in millinewtons — pass 10"]),
    ("minimal-work", {"mu": 30}, ["friction coefficient", "probably in per cent — pass 0.3"]),
    (
        "minimal-work",
        {"mass_kg": {"plastic_cup": 180, "mustard": 270, "shampoo": 250}},
        ["mass_kg['plastic_cup']", "probably in grams — pass 0.18 [kg]"],
    ),
    ("physical-trials", {"mass": 30}, ["probably in grams — pass 0.03 [kg]"]),
    ("physical-trials", {"mu": 30}, ["probably in per cent — pass 0.3"]),
    ("fem-fitting", {"E": 1}, ["E [Pa]", "pad Young's modulus", "probably in MPa — pass 1e+06 [Pa]"]),
    ("fem-fitting", {"mu": 30}, ["probably in per cent — pass 0.3"]),
    ("fem-fitting", {"nu": 45}, ["probably in per cent — pass 0.45"]),
    (
        "fem-fitting",
        {"pad": {"width": 20.0, "length": 40.0, "thickness": 5.0, "nx": 20, "ny": 40, "nz": 5}},
        ["pad['width']", "probably in millimetres — pass 0.02 [m]"],
    ),
    ("peers", {"E": 1}, ["probably in MPa — pass 1e+06"]),
    ("peers", {"mu": 50}, ["probably in per cent — pass 0.5"]),
    (
        "peers",
        {"hertz_block": {"R_mm": 20.0, "a_mm": 1.5, "nu": 30, "fine_mm": 0.45, "depths_mm": [20.0, 40.0]}},
        ["hertz_block['nu']", "probably in per cent — pass 0.3"],
    ),
    ("sensitivity", {"mu": 30}, ["probably in per cent — pass 0.3"]),
    ("sensitivity", {"force_range": [20000, 35000]}, ["probably in millinewtons — pass 20 [N]"]),
    ("sensitivity", {"length": 30}, ["length [m]", "probably in millimetres — pass 0.03 [m]"]),
    ("fem-validation", {"nus": [30, 45]}, ["nus", "probably in per cent — pass 0.3"]),
    ("fem-validation", {"winkler_h": 1}, ["winkler_h [m]", "probably in millimetres — pass 0.001 [m]"]),
    ("fem-validation", {"delta_sweep": [0.5, 1.0]}, ["probably in millimetres — pass 0.0005 [m]"]),
    ("parametric-surfaces", {"example_mu": 30}, ["example_mu", "probably in per cent — pass 0.3"]),
    ("discretization", {"mu": 30}, ["probably in per cent — pass 0.3"]),
    ("ls-fitting", {"mu": 30}, ["probably in per cent — pass 0.3"]),
    # keys in mm: the slip and the value to pass in the key's unit (metres given to an mm key)
    ("peers", {"pad_mm": [0.016, 0.02, 0.005]}, ["pad_mm[0] [mm]", "probably in metres — pass 16 [mm]"]),
    ("fem-fitting", {"deltas_mm": [1000.0]}, ["deltas_mm[0] [mm]", "probably in micrometres — pass 1 [mm]"]),
    (
        "minimal-work",
        {"reach_closing_mm": 1000},
        ["pad compression", "probably in micrometres — pass 1 [mm]"],
    ),
    # files and presets, named by key (a new-user trial got trimesh's "string is not a file")
    ("physical-trials", {"mesh": "/nonexistent.obj"}, ["mesh must be a mesh file in metres", "no file"]),
    ("physical-trials", {"gripper": "robotiq"}, ["gripper must be 'yumi' (the only packaged preset)"]),
    ("physical-trials", {"scheduler": "tcp://localhost:99999"}, ["port '99999' is not a TCP port"]),
    # words
    (
        "wall-stiffness",
        {"top": "lips"},
        ["top must be one of ['auto', 'lip', 'clamped', 'free']; got 'lips'"],
    ),
    ("minimal-work", {"profiles": "FEM"}, ["profiles must be one of ['reach', 'fem']; got 'FEM'"]),
    ("ls-fitting", {"wrench_source": "meshes"}, ["wrench_source must be one of ['continuous', 'mesh']"]),
    (
        "peers",
        {"cases": ["sphere", "cube"]},
        ["cases must be one of ['sphere', 'cylinder', 'elliptic_cylinder'"],
    ),
]


@pytest.mark.parametrize("name, sets, words", CARELESS)
def test_careless_set_values_are_refused_naming_the_likely_unit(name, sets, words, tmp_path):
    with pytest.raises(SystemExit) as exc:
        build_config(name, True, str(tmp_path / "out"), None, sets)
    msg = str(exc.value.code)
    assert msg.startswith(f"{name}: ")
    assert all(w in msg for w in words), msg
    assert not (tmp_path / "out").exists()  # before any work


def test_at_least_twenty_careless_values_name_a_unit():
    named = [w for _, _, words in CARELESS for w in words if "probably in " in w]
    assert len(named) >= 20


@pytest.mark.parametrize(
    "name, sets, match",
    [
        # a soft TPE wall (20 MPa): real, but below the usual 50 MPa of a bottle wall
        ("wall-stiffness", {"E": 2e7}, r"E \[Pa\] = 2e\+07 Pa is below the usual 5e\+07 Pa"),
        ("wall-stiffness", {"force": 400}, r"force \[N\] = 400 N is above the usual 300 N"),
        # a polyurethane-hard pad (500 MPa): above the usual 100 MPa of a gripper pad
        ("fem-fitting", {"E": 5e8}, r"E \[Pa\] = 5e\+08 Pa is above the usual 1e\+08 Pa"),
        ("physical-trials", {"mass": 15}, r"mass \[kg\] = 15 kg is above the usual 10 kg"),
        ("sensitivity", {"mu": 1.8}, r"mu = 1.8 is above the usual 1.5"),
    ],
)
def test_unusual_but_valid_values_warn_and_pass(name, sets, match, tmp_path):
    with pytest.warns(ImplausibleWarning, match=match):
        cfg = build_config(name, True, str(tmp_path), None, sets)
    assert all(cfg[k] == v for k, v in sets.items())


def test_the_cli_refuses_a_modulus_in_mpa_before_any_work(tmp_path, capsys):
    out = tmp_path / "run"
    with pytest.raises(SystemExit) as exc:
        cli.main(["run", "wall-stiffness", "--quick", "--out", str(out), "--set", "E=2500"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "workbench run wall-stiffness: error: wall-stiffness: --set E=2500.0: E [Pa]" in err
    assert "probably in MPa — pass 2.5e+09 [Pa]" in err
    assert not out.exists()


def test_a_sweep_grid_is_judged_by_the_same_keys_before_any_work(tmp_path, capsys):
    out = tmp_path / "sweep"
    with pytest.raises(SystemExit) as exc:
        cli.main(["sweep", "wall-stiffness", "--quick", "--out", str(out), "--grid", "E=[1500,2500]"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "workbench sweep wall-stiffness: error: point {'E': 1500}" in err
    assert "probably in MPa — pass 1.5e+09 [Pa]" in err
    assert not out.exists()  # no point started, no cluster, nothing written


@pytest.mark.parametrize("name", ["sensitivity-engine", "minimal-work-engine"])
def test_max_drift_is_refused_as_a_drift_not_a_jaw_closing(name, tmp_path):
    """``--set max_drift=5`` was refused as "a jaw closing ... (real values: a pad pressed 0.1-5 mm
    into an object ...)"; it is the trials' drift limit, worded as they word it."""
    with pytest.raises(SystemExit) as exc:
        build_config(name, True, str(tmp_path / "out"), None, {"max_drift": 5})
    msg = str(exc.value.code)
    assert "max_drift [m] must be a limit on the object's drift in the gripper in [0, 0.1] m" in msg, msg
    assert "probably in millimetres — pass 0.005 [m]" in msg
    assert "beyond 9 mm and 5 deg of object motion" in msg
    assert "jaw closing" not in msg and "pad pressed" not in msg
    assert not (tmp_path / "out").exists()
    # the same range and words as the trials' own check of the limit (one rule)
    from workbench.engine_trials.trial import TrialPhases

    with pytest.raises(ValueError, match=r"must be a drift limit in \[0, 0\.1\] m; got 5.*9 mm"):
        TrialPhases(max_drift=5)


def test_a_key_names_its_quantity_in_its_own_words():
    """``named`` / ``examples`` replace the range's name and real values in a refusal and in a
    warning; the range (and its unit slips) stay the quantity's."""
    from workbench.runner.experiment_keys import Key

    spec = Key("lift", "m", "lever", named="lift height", examples="robots lift 20-200 mm")
    with pytest.raises(
        ValueError, match=r"^h \[m\] must be a lift height in \(0, 1\] m; got 50.*robots lift"
    ):
        check_key("h", spec, 50)
    with pytest.warns(ImplausibleWarning, match=r"above the usual 0\.3 m of a lift height \(robots lift"):
        check_key("h", spec, 0.5)
    plain = Key("lift", "m", "lever")
    with pytest.raises(ValueError, match=r"must be a lever arm \(an offset on the object\) in \(0, 1\] m"):
        check_key("h", plain, 50)
