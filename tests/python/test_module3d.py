"""warpmesh.mesh3d (issue 30, item 7): numpy volumes (label and threshold
mode, voxel sizes), shape strings and Python functions to tetrahedra,
returned as numpy views with the report, written and converted to meshio;
the same mesh as the command line; bad arguments raise InputError."""
import json
import subprocess

import numpy as np
import pytest

import warpmesh
from conftest import executable, require


def volumes(t):
    p, c = t.points, t.tetrahedra
    a, b, d, e = (p[c[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, d - a), e - a) / 6


def ball(shape=(20, 22, 24), r=6.5, value=4):
    z, y, x = np.indices(shape)
    return np.where((x - 12) ** 2 + (y - 11) ** 2 + (z - 10) ** 2 < r * r, value, 0).astype(np.uint8)


def test_label_volume_with_voxel_size():
    t = warpmesh.mesh3d(ball(), label=4, voxel_size=(0.5, 0.5, 1.0))
    assert t.points.shape[1] == 3 and t.tetrahedra.shape[1] == 4 and t.tetrahedra.dtype == np.int32
    assert not t.points.flags.writeable
    v = volumes(t)
    assert (v > 0).all()
    assert len(t.tetrahedra) == t.report["tetrahedra"] and abs(v.sum() - t.report["volume"]) < 1e-9
    # The ball (radius 6.5 voxels) with voxels 0.5 x 0.5 x 1: an ellipsoid.
    want = 4 / 3 * np.pi * 6.5 ** 3 * 0.5 * 0.5 * 1.0
    assert abs(v.sum() - want) < 0.1 * want
    # Its extent follows the axes: x from voxel i (0.5 mm), z from k (1 mm).
    assert abs(t.points[:, 0].mean() - 12 * 0.5) < 0.05 and abs(t.points[:, 2].mean() - 10 * 1.0) < 0.1
    c = t.report["certified"]
    assert t.certified == (c["min_dihedral_deg"], c["max_dihedral_deg"])
    # Every tetrahedron certified: all-zero background tetrahedra are left out and counted (issue 30).
    assert c["uncertified_tetrahedra"] == 0 and c["certified_tetrahedra"] == len(t.tetrahedra)
    assert t.report["all_zero_left_out"] >= 0 and "all_zero_tetrahedra" not in c
    # The boundary's edges in more than two boundary triangles, counted in the report (issue 30): none on a ball.
    e = np.sort(np.concatenate([t.boundary_faces[:, [0, 1]], t.boundary_faces[:, [1, 2]], t.boundary_faces[:, [2, 0]]]), axis=1)
    counts = np.unique(e, axis=0, return_counts=True)[1]
    assert t.report["nonmanifold_boundary_edges"] == int((counts > 2).sum()) == 0
    assert t.report["nonmanifold_boundary_vertices"] == 0
    assert set(np.unique(t.regions)) == {1} and len(t.boundary_faces) == len(t.boundary_tags)


def test_threshold_mode_and_labels_alias():
    z, y, x = np.indices((16, 16, 16))
    grey = 100.0 - np.sqrt((x - 8.0) ** 2 + (y - 8.0) ** 2 + (z - 8.0) ** 2) * 20  # 0 at radius 5
    t = warpmesh.mesh3d(grey, iso=0.0)
    assert abs(volumes(t).sum() - 4 / 3 * np.pi * 125) < 0.1 * 4 / 3 * np.pi * 125
    inner = warpmesh.mesh3d(grey, iso=0.0, inside="below")  # the outside of the ball in the box
    assert volumes(inner).sum() > 15 ** 3 - 4 / 3 * np.pi * 125 - 200
    a = warpmesh.mesh3d(ball(), label=4)
    b = warpmesh.mesh3d(ball(), labels="nonzero")
    assert np.array_equal(a.points, b.points) and np.array_equal(a.tetrahedra, b.tetrahedra)


def test_shape_and_function_give_the_cli_mesh(tmp_path):
    meshio = require("meshio", "python3-meshio")
    t = warpmesh.mesh3d("torus:0,0,0,1,0.4", spacing=0.1, verify=True)
    assert t.report["certified"]["verified"]
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--shape", "torus:0,0,0,1,0.4", "--spacing", "0.1",
                    "-o", tmp_path / "cli.vtu", "--quiet"], check=True, timeout=120)
    cli = meshio.read(tmp_path / "cli.vtu")
    assert np.array_equal(cli.points, t.points) and np.array_equal(cli.cells_dict["tetra"], t.tetrahedra)
    t.write(tmp_path / "py.msh")
    m = meshio.read(tmp_path / "py.msh")
    assert np.array_equal(m.cells_dict["tetra"], t.tetrahedra)
    mm = t.to_meshio(boundary=True)
    assert [c.type for c in mm.cells] == ["tetra", "triangle"]
    # A Python function: the unit sphere, the same lattice as the shape.
    f = warpmesh.mesh3d(lambda x, y, z: np.sqrt(x * x + y * y + z * z) - 1, box=(-1, -1, -1, 1, 1, 1), spacing=0.25)
    s = warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.25)
    assert len(f.tetrahedra) == len(s.tetrahedra)
    assert np.allclose(f.points, s.points, atol=1e-12)
    assert "tetrahedra" in t.to_text() and repr(t).startswith("<warpmesh.TetMesh")


def test_face_rule_delaunay_gives_the_cli_mesh_and_blocks_merge_into_it(tmp_path):
    """face_rule="delaunay" is the CLI's --face-rule delaunay mesh, differs
    from parity's, and mesh3d_block with the same face_rule merges into it."""
    meshio = require("meshio", "python3-meshio")
    t = warpmesh.mesh3d("torus:0,0,0,1,0.4", spacing=0.1, face_rule="delaunay")
    assert t.report["face_rule"] == "delaunay"
    assert (volumes(t) > 0).all()
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--shape", "torus:0,0,0,1,0.4", "--spacing", "0.1",
                    "--face-rule", "delaunay", "-o", tmp_path / "cli.vtu", "--quiet"], check=True, timeout=120)
    cli = meshio.read(tmp_path / "cli.vtu")
    assert np.array_equal(cli.points, t.points) and np.array_equal(cli.cells_dict["tetra"], t.tetrahedra)
    assert warpmesh.mesh3d("torus:0,0,0,1,0.4", spacing=0.1).report["face_rule"] == "delaunay"  # the default
    p = warpmesh.mesh3d("torus:0,0,0,1,0.4", spacing=0.1, face_rule="parity")
    assert p.report["face_rule"] == "parity"
    assert not (len(p.points) == len(t.points) and np.array_equal(p.tetrahedra, t.tetrahedra))
    cubes = warpmesh.lattice3d("torus:0,0,0,1,0.4", spacing=0.1)
    half = cubes[0] // 2
    blocks = [warpmesh.mesh3d_block("torus:0,0,0,1,0.4", lo, hi, spacing=0.1, face_rule="delaunay")
              for lo, hi in [((0, 0, 0), (half, cubes[1], cubes[2])), ((half, 0, 0), cubes)]]
    merged = warpmesh.merge_blocks(blocks)
    assert np.array_equal(merged.points, t.points) and np.array_equal(merged.tetrahedra, t.tetrahedra)


@pytest.mark.parametrize("call, message", [
    (lambda: warpmesh.mesh3d(np.zeros((4, 4))), "3D array"),
    (lambda: warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.2, face_rule="Delaunay"), "^face_rule expects 'parity' or 'delaunay'"),
    (lambda: warpmesh.mesh3d_block("sphere:0,0,0,1", (0, 0, 0), (1, 1, 1), spacing=0.2, face_rule=1), "face_rule"),
    (lambda: warpmesh.mesh3d(ball(), label=4, iso=1), "exclude each other"),
    (lambda: warpmesh.mesh3d(ball(), label=9), "empty"),
    (lambda: warpmesh.mesh3d(ball(), label=4, voxel_size=(1, 0, 1)), "voxel_size"),
    (lambda: warpmesh.mesh3d("sphere:0,0,0,1"), "spacing is required"),
    (lambda: warpmesh.mesh3d("sphere:0,0,0", spacing=0.1), "sphere"),
    (lambda: warpmesh.mesh3d(lambda x, y, z: x, spacing=0.1), "box="),
    # Issue 50: the user's exception in its own words, not pybind11's wrapping with a traceback.
    (lambda: warpmesh.mesh3d(lambda x, y, z: 1 / 0, box=(0, 0, 0, 1, 1, 1), spacing=0.2),
     r"^the level-set function raised ZeroDivisionError: division by zero$"),
    (lambda: warpmesh.mesh3d(lambda x, y, z: float("nan"), box=(0, 0, 0, 1, 1, 1), spacing=0.2),
     r"^the level-set function gave f\(.*\), which is not a finite number$"),
    (lambda: warpmesh.mesh3d(ball(), label=4, spacing=-1), "spacing"),
])
def test_bad_arguments_raise_input_error(call, message):
    with pytest.raises(warpmesh.InputError, match=message):
        call()


def test_graded_keywords():
    """graded=, max_size=, grading= (issue 48): the CLI's --graded, --max-size,
    --grading; a graded ball has the uniform one's boundary with fewer
    tetrahedra, its edges within max_size; several materials are refused."""
    u = warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1)
    g = warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, max_size=0.45)
    assert len(g.tetrahedra) < len(u.tetrahedra) and len(g.boundary_faces) == len(u.boundary_faces)
    r = g.report["graded"]
    assert r["max_size"] == 0.45 and r["grading_buffer"] == 0 and r["template_tetrahedra"] > 0
    assert warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, grading=1.5).report["graded"]["grading_buffer"] == 2
    p, t = g.points, g.tetrahedra
    edges = np.concatenate([p[t[:, i]] - p[t[:, j]] for i in range(4) for j in range(i + 1, 4)])
    assert np.linalg.norm(edges, axis=1).max() <= 0.45 * (1 + 1e-12)
    with pytest.raises(warpmesh.InputError, match="graded meshes of several materials are not built yet"):
        warpmesh.mesh3d(shapes="1=sphere:0,0,0,1;2=sphere:0,0,0,0.5", spacing=0.2, graded=True)
    with pytest.raises(warpmesh.InputError, match="^max_size 0.1 is below 2 \\* spacing"):
        warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, max_size=0.1)
