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


def nifti1(path, volume, affine):
    """A minimal single-file NIfTI-1 (.nii) of a uint8 volume (z, y, x) with
    an sform voxel-to-world matrix (the qform left unset)."""
    import struct
    nz, ny, nx = volume.shape
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 2, 8)  # datatype uint8, bitpix
    spacing = np.linalg.norm(affine[:3, :3], axis=0)
    struct.pack_into("<8f", h, 76, 1.0, *spacing, 1, 1, 1, 1)
    struct.pack_into("<fff", h, 108, 352.0, 1.0, 0.0)  # vox_offset, scl_slope, scl_inter
    h[123] = 2  # xyzt_units: mm
    struct.pack_into("<hh", h, 252, 0, 1)  # qform_code, sform_code
    for r in range(3):
        struct.pack_into("<4f", h, 280 + 16 * r, *affine[r])
    h[344:348] = b"n+1\0"
    path.write_bytes(bytes(h) + np.ascontiguousarray(volume, dtype=np.uint8).tobytes())


@pytest.mark.parametrize("fixture", ["nrrd", "nifti"])
def test_read_volume_gives_the_cli_mesh(root, tmp_path, fixture):
    """Issue 49, item 6: read_volume reads a file as the CLI does (its samples
    and voxel-to-world matrix: the bundled crop's permuted, flipped NRRD
    directions, a NIfTI's sform), and mesh3d of what it returns — or of the
    path as a str — is the CLI's mesh of the file, point for point."""
    meshio = require("meshio", "python3-meshio")
    if fixture == "nrrd":
        path = root / "tests" / "data" / "brain_crop22_labels.nrrd"
        options, flags = {"label": 26, "spacing": 1.5}, ["--label", "26", "--spacing", "1.5"]
    else:
        path = tmp_path / "ball.nii"
        affine = np.array([[0, 0, -1.5, 40], [1.25, 0, 0, -7], [0, 1, 0, 3], [0, 0, 0, 1]], float)
        nifti1(path, ball((20, 22, 24), 6.5, 4), affine)
        options, flags = {"label": 4}, ["--label", "4"]
    v = warpmesh.read_volume(path)
    assert v.units == "mm" and v.integer_valued and v.source == str(path)
    if fixture == "nrrd":
        assert v.shape == (22, 22, 22) and v.format == "NRRD"
        # space directions (0,1,0) (0,0,-1) (1,0,0), origin (2,-33,5): voxel (i, j, k) at (2 + k, -33 + i, 5 - j).
        assert np.array_equal(v.affine, [[0, 0, 1, 2], [1, 0, 0, -33], [0, -1, 0, 5], [0, 0, 0, 1]])
        assert (np.asarray(v) == 26).sum() > 100
    else:
        assert np.allclose(v.affine, affine) and v.format == "NIfTI-1"
        assert np.array_equal(np.asarray(v), ball((20, 22, 24), 6.5, 4))
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", str(path), *flags, "-o", tmp_path / "cli.vtu", "--quiet"],
                   check=True, timeout=120)
    cli = meshio.read(tmp_path / "cli.vtu")
    for t in (warpmesh.mesh3d(v, **options), warpmesh.mesh3d(str(path), **options)):
        assert len(t.tetrahedra) > 500
        assert np.array_equal(cli.points, t.points) and np.array_equal(cli.cells_dict["tetra"], t.tetrahedra)
    # The bare array with spacing and origin but no direction is another mesh (the 245 054 against 245 169).
    bare = warpmesh.mesh3d(np.asarray(v), voxel_size=v.spacing, origin=v.origin, **options)
    assert bare.points.shape != cli.points.shape or not np.array_equal(bare.points, cli.points)
    # Blocks of a Volume merge into the same mesh.
    cubes = warpmesh.lattice3d(v, **options)
    blocks = [warpmesh.mesh3d_block(v, lo, hi, **options)
              for lo, hi in [((0, 0, 0), (cubes[0] // 2, cubes[1], cubes[2])), ((cubes[0] // 2, 0, 0), cubes)]]
    assert np.array_equal(warpmesh.merge_blocks(blocks).points, cli.points)
    with pytest.raises(warpmesh.InputError, match="carries its origin"):
        warpmesh.mesh3d(v, origin=(1, 2, 3), **options)
    with pytest.raises(warpmesh.InputError, match="brain_crop22|no such|cannot"):
        warpmesh.read_volume(tmp_path / "brain_crop22_missing.nrrd")


def test_graded_keywords():
    """graded=, max_size=, grading= (issue 48): the CLI's --graded, --max-size,
    --grading; a graded ball has the uniform one's boundary with fewer
    tetrahedra, its edges within max_size; several materials (shapes=) too,
    each coarse cell in one material."""
    u = warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1)
    g = warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, max_size=0.45)
    assert len(g.tetrahedra) < len(u.tetrahedra) and len(g.boundary_faces) == len(u.boundary_faces)
    r = g.report["graded"]
    assert r["max_size"] == 0.45 and r["grading_buffer"] == 0 and r["template_tetrahedra"] > 0
    assert warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, grading=1.5).report["graded"]["grading_buffer"] == 2
    p, t = g.points, g.tetrahedra
    edges = np.concatenate([p[t[:, i]] - p[t[:, j]] for i in range(4) for j in range(i + 1, 4)])
    assert np.linalg.norm(edges, axis=1).max() <= 0.45 * (1 + 1e-12)
    two = "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"
    mu = warpmesh.mesh3d(shapes=two, spacing=0.1)
    mg = warpmesh.mesh3d(shapes=two, spacing=0.1, graded=True, max_size=0.45)
    assert len(mg.tetrahedra) < len(mu.tetrahedra) and len(mg.boundary_faces) == len(mu.boundary_faces)
    assert set(np.unique(mg.regions)) == {1, 2} and mg.report["graded"]["template_tetrahedra"] > 0
    with pytest.raises(warpmesh.InputError, match="^max_size 0.1 is below 2 \\* spacing"):
        warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.1, graded=True, max_size=0.1)
