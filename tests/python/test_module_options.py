"""The Python keywords are the library's option tables (issue 46): every
entry of the 2D table is a keyword of mesh, mesh_shape and mesh_shapes, every
entry of the 3D table one of mesh3d; no keyword is outside the tables but the
inputs' own; the docstrings list every entry with the table's help; the CLI's
help lists the same flags; a bad value raises OptionError naming the keyword
in the library's words (never a CLI flag)."""
import inspect
import pathlib
import subprocess

import numpy as np
import pytest

import warpmesh
from warpmesh import _core
from conftest import executable

ROOT = pathlib.Path(__file__).resolve().parents[2]
TABLE2D = _core.option_table("mesh2d")
TABLE3D = _core.option_table("mesh3d")

# Keywords that are not options of the mesher but describe its input, or the call.
INPUT_KEYWORDS = {
    warpmesh.mesh: {"iso", "inside", "labels", "materials", "pixel_size", "threads"},
    warpmesh.mesh_shape: {"threads"},
    warpmesh.mesh_shapes: {"threads"},
    warpmesh.mesh3d: {"label", "labels", "iso", "inside", "materials", "shapes", "voxel_size", "origin", "box", "threads",
                      "max_memory_mb"},
}


# Options of several materials, not taken by the one-region mesh_shape.
MATERIALS_ONLY = {"background", "max_size_of"}


def keywords(function):
    return {p.name for p in inspect.signature(function).parameters.values() if p.kind == p.KEYWORD_ONLY}


@pytest.mark.parametrize("function", list(INPUT_KEYWORDS), ids=lambda f: f.__name__)
def test_the_keywords_are_the_table_and_the_inputs(function):
    table = {o["name"] for o in (TABLE3D if function is warpmesh.mesh3d else TABLE2D)}
    if function is warpmesh.mesh_shape:
        table -= MATERIALS_ONLY
    assert table <= keywords(function), table - keywords(function)
    assert keywords(function) - table == INPUT_KEYWORDS[function]


def test_the_docstrings_are_the_tables():
    for function, table in ((warpmesh.mesh, TABLE2D), (warpmesh.mesh3d, TABLE3D)):
        doc = " ".join(function.__doc__.split())
        for o in table:
            if function is warpmesh.mesh and o["name"] == "spacing":
                continue  # documented with the image's units
            assert f" {o['name']} " in doc, o["name"]
            assert " ".join(o["help"].split()) in doc, o["name"]
            assert "--" not in o["help"], o["name"]  # options named as keywords
    assert "separating rule" not in warpmesh.mesh.__doc__  # issue 50: materials take every rule but maxmin
    assert "bcc_delaunay.cert" in warpmesh.mesh3d.__doc__


def test_the_cli_help_lists_the_same_flags():
    for command, table in (("mesh", TABLE2D), ("mesh3d", TABLE3D)):
        help = subprocess.run([executable("WARPMESH_EXE"), command, "--help"], capture_output=True, text=True,
                              check=True).stdout
        for o in table:
            assert f"\n  {o['flag']} " in help, (command, o["flag"])


def test_every_entry_refuses_a_bad_value_naming_the_keyword():
    for o in TABLE2D:
        bad = "x!" if o["kind"] in ("choice", "text") else ({1: "big"} if o["kind"] == "pairs" else "x!")
        if o["kind"] == "flag":
            continue  # any value is true or false, as bool() reads it
        with pytest.raises(warpmesh.OptionError) as e:
            warpmesh.mesh_shapes("1=circle:0,0,4", **{o["name"]: bad})
        assert str(e.value).startswith(o["name"]) and "--" not in str(e.value), str(e.value)
        assert isinstance(e.value, warpmesh.InputError) and isinstance(e.value, ValueError)


def test_lattice_keyword_is_the_cli_lattice(tmp_path):
    # Issue 50: no Python keyword for --lattice rhombic.
    import meshio

    vtu = tmp_path / "r.vtu"
    subprocess.run([executable("WARPMESH_EXE"), "mesh", "--shape", "circle:0,0,5", "--spacing", "0.5", "--lattice",
                    "rhombic", "-o", str(vtu), "--quiet"], check=True)
    ref = meshio.read(vtu)
    m = warpmesh.mesh_shape("circle:0,0,5", spacing=0.5, lattice="rhombic")
    assert m.report["lattice_metric"] == "rhombic"
    assert np.array_equal(ref.points[:, :2], m.points) and np.array_equal(ref.cells_dict["triangle"], m.triangles)
    img = np.zeros((30, 30), np.uint8)
    img[8:22, 8:22] = 200
    assert warpmesh.mesh(img, lattice="rhombic").report["lattice_metric"] == "rhombic"
    with pytest.raises(warpmesh.OptionError, match="^lattice='rhombic' is not available with several materials"):
        warpmesh.mesh_shapes("1=circle:0,0,5", lattice="rhombic")
    with pytest.raises(warpmesh.OptionError, match="^graded=True is not available with lattice='rhombic'"):
        warpmesh.mesh_shape("circle:0,0,5", lattice="rhombic", graded=True)


def test_the_default_rule_is_the_fan_rule_as_the_clis(tmp_path):
    # Issue 50: the default is the fan rule (the paper's 18.4349 deg on every
    # input, several materials included), in Python as in the CLI; on the
    # rhombic lattice, which has no fan rule, separating.
    assert warpmesh.mesh.__kwdefaults__["rule"] is None and "fan (default)" in warpmesh.mesh.__doc__
    labels = warpmesh.read_image(str(ROOT / "mesher/examples/abdomen_axial_z040_labels16.pgm"))
    m = warpmesh.mesh(labels, materials="all", spacing=2)
    assert m.report["rule"] == "fan" and m.report["certified"]["min_angle_deg"] >= 18.4349
    assert warpmesh.mesh_shape("circle:0,0,5").report["rule"] == "fan"
    assert warpmesh.mesh_shapes("1=circle:0,0,5;2=circle:3,0,3").report["rule"] == "fan"
    assert warpmesh.mesh_shape("circle:0,0,5", lattice="rhombic").report["rule"] == "separating"
    assert warpmesh.mesh_shape("circle:0,0,5", rule="separating").report["rule"] == "separating"
    with pytest.raises(warpmesh.OptionError, match="^rule='fan' is not available with lattice='rhombic'"):
        warpmesh.mesh_shape("circle:0,0,5", lattice="rhombic", rule="fan")


def test_messages_name_keywords_where_the_cli_names_flags(tmp_path):
    with pytest.raises(warpmesh.OptionError, match=r"^grading applies to graded meshes: add graded=True"):
        warpmesh.mesh_shape("circle:0,0,5", grading=1.5)
    r = subprocess.run([executable("WARPMESH_EXE"), "mesh", "--shape", "circle:0,0,5", "--grading", "1.5", "-o",
                        str(tmp_path / "m.vtu")], capture_output=True, text=True)
    assert r.returncode == 2 and "--grading applies to graded meshes: add --graded" in r.stderr
    with pytest.raises(warpmesh.OptionError, match=r"^face_rule expects 'parity' or 'delaunay', got 'x'"):
        warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.3, face_rule="x")
    with pytest.raises(warpmesh.OptionError, match=r"max_memory"):
        warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.3, max_memory=0)
