"""Careless inputs to the object-wall contract: a mesh that is not
watertight, in millimetres, or with sections that are not star-shaped; locations off the
surface or an odd number of them; a wall thickness <= 0; a locations file in another
format; a non-numeric ``--set``.  Each must stop with a message naming what was
expected, what was got and the fix — through ``workbench run wall-stiffness`` (in
process) and through the library — and before any FEM assembly: ``WallGeometry.build``
is replaced by a tripwire, so nothing here builds a wall.  The same file format feeds
``workbench run minimal-work``, checked at the end.

Synthetic geometry only: an open cup (a revolved 0.5 mm wall, r = 20 mm, 40 mm tall),
a C-shaped and a dumbbell-shaped extrusion."""

import json
import re

import numpy as np
import pytest
import trimesh

import workbench.fem.object_wall
from workbench.fem.mesh_wall import radial_surface
from workbench.fem.object_wall import object_wall, wall_geometry
from workbench.fem.wall_grasps import grasp_pairs, read_locations
from workbench.plausible import ImplausibleWarning
from workbench.runner.cli import main

R, T, H = 0.020, 0.5e-3, 0.040  # cup radius, wall, height [m]
Z = 0.020  # grasp height, mid side wall
FIX = "the locations must lie on this mesh, in its frame and in metres"


class _Assembly(Exception):
    """Raised instead of assembling a wall: the input got past every check."""


@pytest.fixture(autouse=True)
def _no_assembly(monkeypatch):
    def build(self, *args, **kwargs):
        raise _Assembly("the input passed validation and reached the FEM assembly")

    monkeypatch.setattr(workbench.fem.object_wall.WallGeometry, "build", build)


def _cup() -> trimesh.Trimesh:
    section = np.array([(0.0, 0.0), (R, 0.0), (R, H), (R - T, H), (R - T, T), (0.0, T)])
    m = trimesh.creation.revolve(section, sections=32)  # this order winds it outward
    assert m.is_watertight
    return m


def _band(outer: np.ndarray, inner: np.ndarray, closed: bool) -> trimesh.Trimesh:
    """A 40 mm prism of the band between two polylines (x, y) [m] of equal length."""
    n = len(outer)
    faces = []
    for i in range(n if closed else n - 1):
        j = (i + 1) % n
        faces += [[i, j, n + j], [i, n + j, n + i]]
    m = trimesh.creation.extrude_triangulation(np.r_[outer, inner], np.array(faces), H)
    trimesh.repair.fix_normals(m)
    assert m.is_watertight
    return m


def _c_shape() -> trimesh.Trimesh:
    """A thick C (radii 10..20 mm, open over ±40°): the box centre lies in its hollow and the
    rays through the opening miss it."""
    th = np.linspace(np.radians(40), np.radians(320), 30)
    ring = np.c_[np.cos(th), np.sin(th)]
    return _band(0.02 * ring, 0.01 * ring, closed=False)


def _dumbbell() -> trimesh.Trimesh:
    """A 0.5 mm wall round two 20 mm discs joined by a 12 mm neck: rays leaving the neck
    cross the wall again at a lobe (4 hits)."""
    r, d, w = 0.02, 0.03, 0.006
    b = np.arcsin(w / r)
    a = np.linspace(-np.pi + b, np.pi - b, 40)
    right = np.c_[d + r * np.cos(a), r * np.sin(a)]
    top = np.c_[np.linspace(d - r * np.cos(b), -d + r * np.cos(b), 8)[1:-1], np.full(6, w)]
    outer = np.r_[right, top, -right, -top]  # counter-clockwise
    edge = np.roll(outer, -1, axis=0) - outer
    en = np.c_[edge[:, 1], -edge[:, 0]] / np.linalg.norm(edge, axis=1)[:, None]  # outward edge normals
    vn = en + np.roll(en, 1, axis=0)
    vn /= np.einsum("ij,ij->i", vn, en)[:, None]  # mitred: both adjacent edges move by T
    return _band(outer, outer - T * vn, closed=True)


def _at(r: float, z: float, deg: float = 45.0) -> list[float]:
    a = np.radians(deg)
    return [r * np.cos(a), r * np.sin(a), z]


def _grasps(first: list[float]) -> list[list[float]]:
    """Two grasps at 45° (2n = 4 points: i and i + 2 one grasp), ``first`` replacing point 0."""
    return [first, _at(R, Z - 0.005), _at(-R, Z), _at(-R, Z - 0.005)]


GOOD = _grasps(_at(R, Z))
LOCATIONS = {
    "good": GOOD,
    "out_2mm": _grasps(_at(R + 2e-3, Z)),  # at 45°: inside the box, 2 mm outside the wall
    "in_2mm": _grasps(_at(R - 2e-3, Z)),  # inside the cup
    "beyond_box": _grasps(_at(R + 2e-3, Z, deg=0.0)),  # at 0°: 2 mm beyond the box too
    "out_2mm_base": _grasps(_at(R + 2e-3, 1e-3)),  # below the side wall (z from 2 mm): not on it
    "odd": GOOD[:3],
}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("careless")
    cup = _cup()
    cup.export(d / "cup.obj")
    holed = cup.copy()
    holed.update_faces(np.arange(len(holed.faces)) != 5)  # one triangle missing
    holed.export(d / "holed.obj")
    cup.copy().apply_scale(1000.0).export(d / "cup_mm.obj")
    _c_shape().export(d / "c_shape.obj")
    _dumbbell().export(d / "dumbbell.obj")
    for name, pts in LOCATIONS.items():
        (d / f"{name}.json").write_text(json.dumps({"stiffness_locations": pts}))
    (d / "wrong_key.json").write_text(json.dumps({"locations": GOOD}))
    (d / "not_json.json").write_text("stiffness_locations: [[0.02, 0, 0.02]]")
    (d / "ragged.json").write_text(json.dumps({"stiffness_locations": [GOOD[0], GOOD[1][:2]]}))
    (d / "map_text.json").write_text(
        json.dumps({"stiffness_locations": GOOD, "stiffness_map": ["stiff"] * 4})
    )
    return d


def _cli_error(capsys, tmp_path, files, *sets: str) -> str:
    """``workbench run wall-stiffness`` with ``--set`` items (file names resolved in
    ``files``) must fail: exit status 2 with a message on stderr (checks before any work) or
    a ValueError (checks on the ray-cast wall, before assembly).  Returns the message."""
    argv = ["run", "wall-stiffness", "--out", str(tmp_path / "out")]
    for item in sets:
        key, value = item.split("=", 1)
        if key in ("object", "locations"):
            value = str(files / value)
        argv += ["--set", f"{key}={value}"]
    try:
        main(argv)
    except SystemExit as exc:
        assert exc.code == 2, exc.code
        return capsys.readouterr().err
    except ValueError as exc:
        return str(exc)
    pytest.fail(f"accepted: {sets}")


def _has(text: str, *words: str) -> None:
    missing = [w for w in words if w not in text]
    assert not missing, f"{missing} not in: {text}"


CLI_CASES = {
    # id: (--set items, words naming what was expected, what was got and the fix)
    "not watertight": (
        ["object=holed.obj", "locations=good.json"],
        ["holed.obj", "not watertight", "must be closed", "open edges", "repair it", "fill_holes"],
    ),
    "millimetres": (
        ["object=cup_mm.obj", "locations=good.json"],
        [
            "cup_mm.obj",
            "spans 40 m",
            "more than",
            "probably in millimetres",
            "re-export it in metres",
            "0.001",
        ],
    ),
    "C section": (
        ["object=c_shape.obj", "locations=good.json"],
        ["not star-shaped about the axis", "misses the mesh", "star-shaped about it"],
    ),
    "dumbbell section": (
        ["object=dumbbell.obj", "locations=good.json"],
        ["not star-shaped about the axis", "hits it 4 times", "star-shaped about it"],
    ),
    "2 mm outside": (
        ["object=cup.obj", "locations=out_2mm.json"],
        ["location 0", "off the object's surface"],
    ),
    "2 mm inside": (["object=cup.obj", "locations=in_2mm.json"], ["location 0", "off the object's surface"]),
    "2 mm beyond the box": (
        ["object=cup.obj", "locations=beyond_box.json"],
        ["location 0", "outside the object's box", "2.00 mm beyond it", "at most 1 mm", FIX],
    ),
    "2 mm off below the side wall": (
        ["object=cup.obj", "locations=out_2mm_base.json"],
        ["location 0", "off the object's mesh", "2.00 mm from it", "at most 1 mm", "below the side wall"]
        + [FIX],
    ),
    "odd number": (
        ["object=cup.obj", "locations=odd.json"],
        ["odd.json", "must hold 2n points", "two jaws", "got 3", "add the missing one"],
    ),
    "thickness 0": (
        ["object=cup.obj", "locations=good.json", "thickness=0"],
        ["thickness [m] must be a wall thickness in [1e-05, 0.05] m", "got 0.0", "PET bottle 0.2-0.5 mm"],
    ),
    "thickness -1e-3": (
        ["object=cup.obj", "locations=good.json", "thickness=-1e-3"],
        ["thickness", "-0.001 is negative", "takes no negative values", "--set thickness=0.0005"],
    ),
    "thickness 1e-9 (a slip of units)": (
        ["object=cup.obj", "locations=good.json", "thickness=1e-9"],
        ["thickness [m] must be a wall thickness in [1e-05, 0.05] m", "got 1e-09", "PET bottle 0.2-0.5 mm"],
    ),
    "jaw in millimetres": (
        ["object=cup.obj", "locations=good.json", "jaw=[20,40]"],
        ["jaw[0] [m] must be a pad size", "got 20.0", "probably in millimetres — pass 0.02 [m]"],
    ),
    "locations without object": (
        ["locations=good.json"],
        ["good.json needs object=PATH.obj", "would ignore the locations"],
    ),
    "thickness not a number": (
        ["object=cup.obj", "locations=good.json", "thickness=thin"],
        ["thickness expects float", "'thin' is not a number", "--set thickness=0.0005"],
    ),
    "locations without the key": (
        ["object=cup.obj", "locations=wrong_key.json"],
        ["wrong_key.json", "expected a JSON object with 'stiffness_locations'", "got keys ['locations']"],
    ),
    "locations not JSON": (
        ["object=cup.obj", "locations=not_json.json"],
        ["not_json.json", "expected a JSON object", "not JSON"],
    ),
    "ragged locations": (
        ["object=cup.obj", "locations=ragged.json"],
        ["ragged.json", "(2n, 3)", "one [x, y, z] of numbers per point", "give every point three numbers"],
    ),
    "stiffness_map not numbers": (
        ["object=cup.obj", "locations=map_text.json"],
        ["map_text.json", "'stiffness_map' must hold one value [N/m] per location", "not all numbers"],
    ),
    "no locations": (["object=cup.obj"], ["needs locations=PATH.json", "got none", "--set locations="]),
    "missing object file": (
        ["object=nowhere.obj", "locations=good.json"],
        ["object=", "nowhere.obj: no such file", "give the path of a watertight .obj mesh in metres"],
    ),
    "missing locations file": (
        ["object=cup.obj", "locations=nowhere.json"],
        ["locations=", "nowhere.json: no such file"],
    ),
    "unknown top": (
        ["object=cup.obj", "locations=good.json", "top=open"],
        ["top must be one of", "'lip'", "got 'open'"],
    ),
}


@pytest.mark.parametrize("case", list(CLI_CASES))
def test_cli_refuses_careless_input(case, capsys, tmp_path, files):
    sets, words = CLI_CASES[case]
    err = _cli_error(capsys, tmp_path, files, *sets)
    _has(err, *words)
    # every remedy named is one a command-line user has (no library-only keyword arguments)
    assert not any(w in err for w in ("allow_scale", "pass a centre", "z_range")), err
    if "2 mm" in case and "beyond" not in case and "below" not in case:
        assert re.search(r"is -?[12]\.\d\d mm off it \(radially", err), err
        _has(err, "at most 1 mm", FIX)
    assert not (tmp_path / "out" / "rows.jsonl").exists()  # no grasp was squeezed


def test_cli_good_input_reaches_the_assembly(tmp_path, files):
    """The same cup and locations, well formed, pass every check (the tripwire fires)."""
    with pytest.raises(_Assembly):
        main(
            ["run", "wall-stiffness", "--out", str(tmp_path), "--set", f"object={files / 'cup.obj'}"]
            + ["--set", f"locations={files / 'good.json'}"]
        )


# ----------------------------------------------------------------- the library calls


@pytest.fixture(scope="module")
def cup_surface():
    cup = _cup()
    return cup, radial_surface(cup)


def test_library_refuses_careless_meshes(files):
    load = {
        n: trimesh.load(files / f"{n}.obj", force="mesh") for n in ("holed", "cup_mm", "c_shape", "dumbbell")
    }
    with pytest.raises(ValueError, match="not watertight") as exc:
        wall_geometry(load["holed"])
    _has(str(exc.value), "must be closed", "open edges", "fill_holes")
    with pytest.raises(ValueError, match="probably in millimetres") as exc:
        object_wall(load["cup_mm"])
    _has(str(exc.value), "spans 40 m", "pass units='mm'")
    assert wall_geometry(load["cup_mm"], units="mm").surface.z_range[1] < H  # the fix works
    for name, got in (("c_shape", "misses the mesh"), ("dumbbell", "hits it 4 times")):
        with pytest.raises(ValueError, match="not star-shaped about the axis") as exc:
            object_wall(load[name])
        _has(str(exc.value), got, "star-shaped about it: one body, no handle")
        assert "pass a centre" not in str(exc.value)  # object_wall takes no centre: not a fix to offer


@pytest.mark.parametrize("thickness", [0.0, -1e-3, float("nan"), "0.5e-3"])
def test_library_refuses_a_thickness_that_is_not_positive(thickness):
    with pytest.raises(
        ValueError, match=r"thickness must be a (wall thickness in \[1e-05, 0.05\] m|number)"
    ) as exc:
        object_wall(_cup(), thickness=thickness)  # before the mesh is read, long before assembly
    _has(str(exc.value), f"got {thickness!r}")


@pytest.mark.parametrize(
    "name, words",
    [
        ("out_2mm", ["location 0", "mm off it", "at most 1 mm", FIX]),
        ("in_2mm", ["location 0", "mm off it", "at most 1 mm", FIX]),
        ("beyond_box", ["outside the object's box", "2.00 mm beyond it", FIX]),
        ("out_2mm_base", ["off the object's mesh", "2.00 mm from it", "below the side wall", FIX]),
        ("odd", ["must hold 2n points", "got 3", "add the missing one"]),
    ],
)
def test_library_refuses_careless_locations(cup_surface, name, words):
    mesh, surface = cup_surface
    with pytest.raises(ValueError) as exc:
        grasp_pairs(np.array(LOCATIONS[name]), surface, mesh=mesh)
    _has(str(exc.value), *words)


def test_points_off_the_side_wall_are_checked_only_with_the_mesh(cup_surface):
    mesh, surface = cup_surface
    base = np.array(LOCATIONS["out_2mm_base"])
    grasp_pairs(base, surface)  # without the mesh nothing is known below the side wall
    a, b = grasp_pairs(np.array(GOOD), surface, mesh=mesh)
    assert a.shape == b.shape == (2, 3)


def test_read_locations_names_the_file_and_the_format(files):
    for name, words in [
        ("wrong_key", ["wrong_key.json", "'stiffness_locations'", "got keys ['locations']"]),
        ("not_json", ["not_json.json", "not JSON"]),
        ("odd", ["odd.json", "2n points", "got 3"]),
        ("ragged", ["ragged.json", "(2n, 3)"]),
    ]:
        with pytest.raises(ValueError) as exc:
            read_locations(files / f"{name}.json")
        _has(str(exc.value), *words)


# ---------------------------------------------------------------- minimal-work's inputs


def _minimal_work_error(capsys, tmp_path, data_dir) -> str:
    """``workbench run minimal-work`` must fail: exit status 2 before any work (a missing
    file) or a ValueError (a malformed one).  Returns the message."""
    argv = ["run", "minimal-work", "--quick", "--out", str(tmp_path / "out")]
    argv += ["--set", f"data_dir={data_dir}", "--set", 'objects=["plastic_cup"]']
    try:
        main(argv)
    except SystemExit as exc:
        assert exc.code == 2
        return capsys.readouterr().err
    except ValueError as exc:
        return str(exc)
    raise AssertionError("minimal-work accepted the careless input")


def _data_dir(tmp_path, smap) -> str:
    d = tmp_path / "objects"
    (d / "meshes").mkdir(parents=True)
    (d / "stiffness_maps").mkdir()
    _cup().export(d / "meshes" / "plastic_cup.obj")
    text = smap if isinstance(smap, str) else json.dumps(smap)
    (d / "stiffness_maps" / "plastic_cup.json").write_text(text)
    return str(d)


def test_minimal_work_broken_data_dir(capsys, tmp_path):
    err = _minimal_work_error(capsys, tmp_path, tmp_path / "nowhere")
    _has(err, "plastic_cup", "not found", "set data_dir to the deformable_objects folder")


@pytest.mark.parametrize(
    "smap, words",
    [
        ("{not json", ["plastic_cup.json", "expected a JSON object", "not JSON"]),
        (
            {"stiffness_map": [1e3] * 4},
            ["plastic_cup.json", "'stiffness_locations'", "got keys ['stiffness_map']"],
        ),
        ({"stiffness_locations": GOOD[:3], "stiffness_map": [1e3] * 3}, ["2n points", "got 3"]),
        (
            {"stiffness_locations": GOOD, "stiffness_map": [1e3] * 3},
            ["one value [N/m] per location", "got 3"],
        ),
        ({"stiffness_locations": GOOD}, ["plastic_cup.json", "'stiffness_map'", "wall-stiffness"]),
    ],
)
def test_minimal_work_wrong_format_map(capsys, tmp_path, smap, words):
    _has(_minimal_work_error(capsys, tmp_path, _data_dir(tmp_path, smap)), *words)


# ---------------------------------------------------------------- wall-nonlinear's grasps


@pytest.mark.parametrize("grasps", ["[]", "[3,3]", "[-1]", "[1.5]", '["a"]', "7"])
def test_wall_nonlinear_refuses_careless_grasps(capsys, tmp_path, grasps):
    with pytest.raises(SystemExit) as exc:
        main(["run", "wall-nonlinear", "--out", str(tmp_path), "--set", f"grasps={grasps}"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "grasps" in err and ("distinct grasp indices" in err or "list" in err), err


@pytest.mark.parametrize(
    "key, value, words",
    [
        ("profiles", "fem_pad", ["profiles must be one of", "'reach'", "'fem'", "fem_pad"]),
        ("nl_work_objects", '["bottle"]', ["nl_work_objects", "bottle", "not objects of this experiment"]),
        # refused at the first grasp or the normaliser fit, minutes in, until the new-user trial
        (
            "mass_kg",
            '{"plastic_cup": 180, "mustard": 0.27, "shampoo": 0.25}',
            ["mass_kg['plastic_cup']", "pass 0.18"],
        ),
        ("mass_kg", '{"plastic_cup": 0.18}', ["mass_kg must give every object", "'mustard'", "'shampoo'"]),
        ("sigma", "1.0", ["sigma must be", "< 1", "1.0"]),
        ("mu", "0", ["mu must be", "> 0"]),
    ],
)
def test_minimal_work_refuses_careless_settings_before_any_work(capsys, tmp_path, key, value, words):
    argv = ["run", "minimal-work", "--quick", "--out", str(tmp_path / "out"), "--set", f"{key}={value}"]
    try:
        main(argv)
    except SystemExit as exc:
        assert exc.code == 2
        err = capsys.readouterr().err
    except ValueError as exc:
        err = str(exc)
    else:
        raise AssertionError("minimal-work accepted the careless setting")
    _has(err, *words)
    assert not (tmp_path / "out" / "rows.jsonl").exists()  # refused before any work


# ------------------------------------------------------------------------ a new-user trial


def test_thickness_in_millimetres_is_refused(capsys, tmp_path, files):
    """0.5 meant as 0.5 mm: a 0.5 m wall on a 40 mm cup was built and called rigid."""
    with pytest.raises(ValueError, match="probably in millimetres — pass 0.0005") as exc:
        wall_geometry(_cup(), thickness=0.5)
    err = _cli_error(capsys, tmp_path, files, "object=cup.obj", "locations=good.json", "thickness=0.5")
    _has(err, "probably in millimetres", "0.0005")
    # a plausible thickness (with a warning) that is still too thick for this small cup
    with pytest.warns(ImplausibleWarning, match="above the usual 0.01 m"):
        with pytest.raises(ValueError, match="more than a fifth of the section's smallest radius") as exc:
            wall_geometry(_cup(), thickness=0.02)
    _has(str(exc.value), "thickness 0.02 m")
    assert "Traceback" not in err


def test_run_time_value_errors_are_one_clean_line(capsys, tmp_path, files):
    """A location 2 mm off the wall is found after the mesh is read (ray casting): the CLI
    prints the message and exits 2 instead of a traceback."""
    with pytest.raises(SystemExit) as exc:
        main(
            [
                "run",
                "wall-stiffness",
                "--out",
                str(tmp_path / "o"),
                "--set",
                f"object={files / 'cup.obj'}",
                "--set",
                f"locations={files / 'out_2mm.json'}",
            ]
        )
    assert exc.value.code == 2
    err = capsys.readouterr().err
    _has(err, "workbench run wall-stiffness: error:", "mm off it", "-v shows the traceback")


def test_unit_messages_name_only_fixes_the_caller_has():
    from workbench.grasp.stiffness_map import StiffnessMap

    P = np.array([[30.0, 0, 0], [0, 30.0, 0], [-30.0, 0, 0], [0, -30.0, 10.0]])  # mm
    with pytest.raises(ValueError, match="millimetres") as exc:
        StiffnessMap(P, np.full(4, 500.0))
    assert "allow_scale" not in str(exc.value)
    with pytest.raises(ValueError, match="millimetres") as exc:
        wall_geometry(_cup().apply_scale(1000.0))
    assert "allow_scale" not in str(exc.value) and "units='mm'" in str(exc.value)


@pytest.mark.parametrize(
    "key, value, word",
    [
        ("force", "0", "(0, 500] N"),
        ("force", "-10", "negative"),
        ("E", "0", "(100000, 1e+12] Pa"),
        ("jaw", "[0.02, 0]", "(0.0001, 0.2] m"),
    ],
)
def test_wall_stiffness_refuses_a_zero_force_e_or_jaw_before_any_work(capsys, tmp_path, key, value, word):
    with pytest.raises(SystemExit) as exc:
        main(["run", "wall-stiffness", "--out", str(tmp_path / "o"), "--set", f"{key}={value}"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    _has(err, key, word, value.split(",")[0].strip("["))
    assert not (tmp_path / "o").exists()
