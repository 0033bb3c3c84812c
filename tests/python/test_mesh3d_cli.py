"""`warpmesh mesh3d` (issue 30): the command line of the 3D mesher, run as a
user runs it: a 3D shape and a labelled NRRD volume meshed into every 3D
format, read back with meshio and compared with the JSON report; options
that have no effect in 3D, bad input and 2D-only formats refused with a
message and nothing written.
"""
import json
import os

import numpy as np
import pytest

from conftest import require, run_mesh3d as mesh3d, write_nrrd


def tet_volumes(points, tets):
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6


def test_sphere_in_every_format_matches_the_report(tmp_path):
    meshio = require("meshio", "python3-meshio")
    outs = ["s.vtu", "s.msh", "s.xdmf", "s.inp", "s.mesh"]
    r = mesh3d(["--shape", "sphere:0,0,0,1", "--spacing", "0.2", "-o", outs[0],
                *[a for o in outs[1:] for a in ("--also", o)], "--report", "r.json", "--verify"], tmp_path)
    report = json.loads((tmp_path / "r.json").read_text())
    assert "tetrahedra" in r.stdout and "certified" in r.stdout and "all-zero background tetrahedra left out: 0" in r.stdout
    assert "non-manifold edges 0, vertices 0" in r.stdout
    assert report["certified"]["verified"] and report["certified"]["uncertified_tetrahedra"] == 0
    assert report["certified"]["min_dihedral_deg"] <= report["min_dihedral_deg"]
    assert report["max_dihedral_deg"] <= report["certified"]["max_dihedral_deg"]
    m = meshio.read(tmp_path / "s.vtu")
    tets = m.cells_dict["tetra"]
    assert len(tets) == report["tetrahedra"] and len(m.points) == report["vertices"]
    vol = tet_volumes(m.points, tets)
    assert (vol > 0).all() and abs(vol.sum() - report["volume"]) < 1e-9
    assert abs(vol.sum() - 4 / 3 * np.pi) < 0.05 * 4 / 3 * np.pi
    for name in outs[1:]:
        other = meshio.read(tmp_path / name)
        assert np.allclose(other.points, m.points, rtol=5e-14, atol=1e-300), name
        assert np.array_equal(other.cells_dict["tetra"], tets), name
    # The boundary triangles lie on the sphere (vertices on the level set).
    f = meshio.read(tmp_path / "s_facets.xdmf")
    tri = f.cells_dict["triangle"]
    assert len(tri) == report["boundary_faces"] and set(f.cell_data["facet_tags"][0]) == {1}
    assert np.allclose(np.linalg.norm(m.points[np.unique(tri)], axis=1), 1, atol=1e-12)


def test_label_volume_in_mm(tmp_path):
    """A labelled NRRD (a ball of label 5 with a cube of label 7 beside it,
    voxels 0.5 mm): --label 5 meshes the ball only, in millimetres."""
    meshio = require("meshio", "python3-meshio")
    z, y, x = np.mgrid[0:24, 0:24, 0:32]
    labels = np.where((x - 11) ** 2 + (y - 12) ** 2 + (z - 12) ** 2 < 64, 5, 0)
    labels[6:18, 6:18, 22:30] = 7
    write_nrrd(tmp_path / "l.nrrd", labels, (0.5, 0.5, 0.5))
    mesh3d(["l.nrrd", "--label", "5", "-o", "b.vtu", "--report", "b.json", "--quiet"], tmp_path)
    report = json.loads((tmp_path / "b.json").read_text())
    m = meshio.read(tmp_path / "b.vtu")
    vol = tet_volumes(m.points, m.cells_dict["tetra"])
    assert (vol > 0).all()
    # A ball of radius ~4 mm (8 voxels of 0.5 mm) centred at (5.5, 6, 6) mm.
    assert abs(vol.sum() - 4 / 3 * np.pi * 4 ** 3) < 0.15 * 4 / 3 * np.pi * 4 ** 3
    assert m.points[:, 0].max() < 10.5  # the cube of label 7 (x >= 11 mm) is not in it
    # Every tetrahedron certified: all-zero background tetrahedra are left out (issue 30).
    assert report["certified"]["uncertified_tetrahedra"] == 0 and isinstance(report["all_zero_left_out"], int)
    assert report["nonmanifold_boundary_edges"] == 0 and report["nonmanifold_boundary_vertices"] == 0  # a ball
    assert report["certified"]["min_dihedral_deg"] <= report["min_dihedral_deg"]
    assert report["max_dihedral_deg"] <= report["certified"]["max_dihedral_deg"]
    # --units pixels: the same volume in voxel coordinates (twice as large).
    mesh3d(["l.nrrd", "--label", "5", "--units", "pixels", "-o", "p.vtu", "--quiet"], tmp_path)
    p = meshio.read(tmp_path / "p.vtu")
    assert abs(tet_volumes(p.points, p.cells_dict["tetra"]).sum() / vol.sum() - 8) < 0.5


def test_volume_edge_faces_are_tagged_domain_border_as_in_2d(tmp_path):
    """Issue 50: where the volume's edge cuts a region off, 3D tagged the
    closing faces boundary (1); 2D tags the image's border domain_border (2).
    A block of label 1 against the volume's face x = 0 (and label 2 beside it,
    inside): its faces on x = 0 are domain_border in every writer that writes
    facet tags (.msh, .xdmf, .inp surfaces, .vtu's vertex markers), one region
    and several materials alike; the other faces stay boundary."""
    meshio = require("meshio", "python3-meshio")
    labels = np.zeros((12, 12, 12), np.uint8)
    labels[3:9, 3:9, 0:6] = 1  # (z, y, x): x = 0 .. 5, on the volume's face x = 0
    labels[3:9, 3:9, 6:9] = 2
    write_nrrd(tmp_path / "edge.nrrd", labels)
    for name, args in (("one", ["--label", "1"]), ("materials", ["--materials", "all"])):
        mesh3d(["edge.nrrd", *args, "-o", f"{name}.msh", "--also", f"{name}.xdmf", "--also", f"{name}.inp",
                "--also", f"{name}.vtu", "--quiet"], tmp_path)
        m = meshio.read(tmp_path / f"{name}.msh")
        assert list(m.field_data["domain_border"]) == [2, 2] and list(m.field_data["boundary"]) == [1, 2], name
        tri = m.cells_dict["triangle"]
        tags = m.cell_data_dict["gmsh:physical"]["triangle"]
        border = tri[tags == 2]
        assert len(border) > 0, name
        assert np.abs(m.points[border, 0]).max() < 1e-9, name  # every domain_border face on x = 0
        on_plane = (np.abs(m.points[tri[tags == 1], 0]) < 1e-9).all(axis=1)
        assert not on_plane.any(), name  # no boundary face lies there
        a = m.points[border]
        area = 0.5 * np.linalg.norm(np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]), axis=1).sum()
        assert abs(area - 25) < 1e-9, (name, area)  # the lattice's section of the block at x = 0: 5 x 5 mm
        f = meshio.read(tmp_path / f"{name}_facets.xdmf")
        assert (f.cell_data["facet_tags"][0] == 2).sum() == len(border), name
        assert "*SURFACE, TYPE=ELEMENT, NAME=domain_border" in (tmp_path / f"{name}.inp").read_text(), name
        v = meshio.read(tmp_path / f"{name}.vtu")
        marker = v.point_data["boundary_marker"]
        inner = np.setdiff1d(np.unique(border), np.unique(tri[tags != 2]))  # vertices of domain_border faces only
        assert len(inner) > 0 and (marker[inner] == 2).all(), name


@pytest.mark.parametrize("args, message", [
    (["--max-cell", "4"], "--max-cell has no effect in 3D (warpmesh mesh3d): 3D graded meshes bound their cells by --max-size"),
    (["--materials", "all"], "materials apply to volumes, not to shapes"),
    (["--max-size-of", "1=0.1"], "per-material sizes are not built in 3D"),
    (["--grading", "1.5"], "--grading applies to graded meshes: add --graded"),
    (["--graded", "--max-size", "0.5"], "--max-size 0.5 is below 2 * spacing = 0.6"),
    (["--slice", "k=3"], "--slice has no effect in 3D"),
    (["--diagonal", "fan"], "--face-rule parity|delaunay"),
    (["--face-rule", "maxmin"], "--face-rule expects 'parity' or 'delaunay', got 'maxmin'"),
    (["--svg-color", "minangle"], "pictures are 2D"),
    (["--optimize"], "--optimize has no effect in 3D"),
])
def test_options_without_effect_in_3d_are_refused(tmp_path, args, message):
    r = mesh3d(["--shape", "sphere:0,0,0,1", "--spacing", "0.3", "-o", "x.vtu", *args], tmp_path, expect=2)
    assert message in r.stderr
    assert not os.listdir(tmp_path)


def test_graded_sphere_keeps_max_size_and_the_uniform_boundary(tmp_path):
    """--graded (issue 48): a conforming mesh (meshio: every tetrahedron
    positive) with the uniform mesh's boundary and volume, fewer tetrahedra,
    every edge within --max-size, and the report's graded figures."""
    meshio = require("meshio", "python3-meshio")
    args = ["--shape", "sphere:0,0,0,1", "--spacing", "0.1"]
    mesh3d([*args, "-o", "u.vtu", "--report", "u.json", "--quiet"], tmp_path)
    r = mesh3d([*args, "--graded", "--max-size", "0.45", "-o", "g.vtu", "--report", "g.json"], tmp_path)
    assert "graded: leaves per level" in r.stdout
    u, g = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("u", "g"))
    assert g["tetrahedra"] < u["tetrahedra"] and g["boundary_faces"] == u["boundary_faces"]
    assert abs(g["volume"] - u["volume"]) < 1e-9 * u["volume"]
    assert g["graded"]["template_tetrahedra"] > 0 and g["graded"]["max_size"] == 0.45
    m = meshio.read(tmp_path / "g.vtu")
    tets = m.cells_dict["tetra"]
    assert (tet_volumes(m.points, tets) > 0).all() and len(tets) == g["tetrahedra"]
    edges = np.concatenate([m.points[tets[:, i]] - m.points[tets[:, j]] for i in range(4) for j in range(i + 1, 4)])
    assert np.linalg.norm(edges, axis=1).max() <= 0.45 * (1 + 1e-12)
    assert abs(np.linalg.norm(edges, axis=1).max() - g["graded"]["longest_edge"]) < 1e-12


def test_face_rule_delaunay_is_the_default_and_never_reported_with_the_parity_certificate(tmp_path):
    """The default face rule is delaunay (--face-rule delaunay gives the same
    file), at its own alphas; the mesh (read back with meshio) differs from
    --face-rule parity's, and each report names its rule and is certified by
    its own certificate: delaunay only by proofs/bcc_delaunay.cert, never by
    proofs/bcc.cert."""
    meshio = require("meshio", "python3-meshio")
    args = ["--shape", "torus:0,0,0,1,0.4", "--spacing", "0.1"]
    r = mesh3d([*args, "-o", "d.vtu", "--report", "d.json"], tmp_path)
    mesh3d([*args, "--face-rule", "delaunay", "-o", "e.vtu", "--quiet"], tmp_path)
    assert (tmp_path / "d.vtu").read_bytes() == (tmp_path / "e.vtu").read_bytes()
    mesh3d([*args, "--face-rule", "parity", "-o", "p.vtu", "--report", "p.json", "--quiet"], tmp_path)
    d, p = (json.loads((tmp_path / f"{n}.json").read_text()) for n in "dp")
    assert d["face_rule"] == "delaunay" and p["face_rule"] == "parity"
    assert "face rule: delaunay" in r.stdout
    if d["certified"] is None:
        assert "bcc_delaunay.cert" in d["uncertified_reason"] and "bcc_delaunay.cert" in r.stderr
        assert "certified: no (" in r.stdout
    else:
        assert d["certified"]["certificate"] == "proofs/bcc_delaunay.cert"
    assert p["certified"]["certificate"] == "proofs/bcc.cert" and p["uncertified_reason"] is None
    assert 11.7 <= d["min_dihedral_deg"] and d["max_dihedral_deg"] <= 161.3
    md, mp = meshio.read(tmp_path / "d.vtu"), meshio.read(tmp_path / "p.vtu")
    assert len(md.cells_dict["tetra"]) == d["tetrahedra"]
    assert (tet_volumes(md.points, md.cells_dict["tetra"]) > 0).all()
    assert not (len(md.points) == len(mp.points) and np.array_equal(md.cells_dict["tetra"], mp.cells_dict["tetra"]))


def test_bad_input_and_2d_formats_write_nothing(tmp_path):
    r = mesh3d(["--shape", "sphere:0,0,0,1", "--spacing", "0.3", "-o", "x.svg"], tmp_path, expect=1)
    assert "2D format" in r.stderr
    r = mesh3d(["--shape", "sphere:0,0,0,1", "-o", "x.vtu"], tmp_path, expect=2)
    assert "spacing is required for a shape" in r.stderr
    r = mesh3d(["--shape", "sphere:0,0,0,-1", "--spacing", "0.3", "-o", "x.vtu"], tmp_path, expect=1)
    assert "sphere" in r.stderr
    labels = np.zeros((6, 6, 6))
    labels[2:4, 2:4, 2:4] = 3
    write_nrrd(tmp_path / "l.nrrd", labels)
    r = mesh3d(["l.nrrd", "--label", "9", "-o", "x.vtu"], tmp_path, expect=1)
    assert "error" in r.stderr
    r = mesh3d(["l.nrrd", "--label", "3", "--iso", "1", "-o", "x.vtu"], tmp_path, expect=2)
    assert sorted(os.listdir(tmp_path)) == ["l.nrrd"]
