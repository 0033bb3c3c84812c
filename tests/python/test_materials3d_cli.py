"""`warpmesh mesh3d --materials` and `--shapes` (issue 47): every material of
a label volume, or analytic materials, in one conforming tetrahedral mesh,
run as a user runs it and read back by real clients: meshio and gmsh read
the .msh (4.1 and 2.2) with a physical group per material and one per
interface, the .xdmf carries cell and facet tags, the .inp element sets and
surfaces that CalculiX solves a three-material problem on; the report's
per-material figures match the files; bad input is refused with a message
and nothing written.
"""
import json
import os
import subprocess

import numpy as np
import pytest

from conftest import executable, require, run_calculix, run_mesh3d as mesh3d, write_nrrd

NESTED = "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"


def labels_volume():
    """A block of label 3, a ball of label 5 inside it, a box of label 7
    beside it and one voxel of label 9 (lost at 1 mm), 0.5 mm voxels."""
    z, y, x = np.mgrid[0:28, 0:28, 0:40]
    labels = np.zeros(x.shape, np.uint8)
    labels[3:25, 3:25, 3:22] = 3
    labels[(x - 12) ** 2 + (y - 14) ** 2 + (z - 14) ** 2 < 36] = 5
    labels[6:22, 6:22, 22:36] = 7
    labels[26, 26, 38] = 9
    return labels


def tet_volumes(points, tets):
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6


def blocks(m, cell_type, key):
    data = [c.data for c in m.cells if c.type == cell_type]
    tags = [d for c, d in zip(m.cells, m.cell_data[key]) if c.type == cell_type]
    return np.concatenate(data), np.concatenate(tags)


@pytest.fixture(scope="module")
def labelled(tmp_path_factory):
    """The label volume meshed with --materials all into every 3D format."""
    d = tmp_path_factory.mktemp("labels")
    write_nrrd(d / "l.nrrd", labels_volume(), (0.5, 0.5, 0.5))
    outs = ["l.msh", "l.vtu", "l.xdmf", "l.inp", "l.mesh"]
    r = mesh3d(["l.nrrd", "--materials", "all", "--spacing", "1", "-o", outs[0],
                *[a for o in outs[1:] for a in ("--also", o)], "--report", "l.json", "--verify"], d)
    mesh3d(["l.nrrd", "--materials", "all", "--spacing", "1", "--msh-version", "2.2", "-o", "l22.msh", "--quiet"], d)
    return d, r, json.loads((d / "l.json").read_text())


def test_report_gives_every_label_with_its_voxels(labelled):
    d, r, report = labelled
    meshio = require("meshio", "python3-meshio")
    by_tag = {m["tag"]: m for m in report["materials"]}
    assert sorted(by_tag) == [3, 5, 7, 9]
    voxels = labels_volume()
    for tag, m in by_tag.items():
        assert m["name"] == f"label_{tag}" and m["voxels"] == int((voxels == tag).sum())
        assert m["reference_volume"] == m["voxels"] * 0.125
    for tag in (3, 5, 7):
        assert abs(by_tag[tag]["relative_error"]) < 0.05, by_tag[tag]
    # The one voxel of label 9 is lost, and named.
    assert by_tag[9]["tetrahedra"] == 0 and report["materials_without_tetrahedra"] == [9]
    assert "material 9 (label_9) got no tetrahedron" in r.stderr
    assert "  5 label_5: " in r.stdout and "interface faces: " in r.stdout
    assert report["face_rule"] == "parity" and report["certified"]["certificate"] == "proofs/bcc.cert"
    assert report["certified"]["verified"] and "each verified" in r.stdout  # --verify: every two-material side
    # The files agree with the report: tetrahedra and volume per region.
    m = meshio.read(d / "l.vtu")
    tets, region = m.cells_dict["tetra"], m.cell_data["region"][0]
    vol = tet_volumes(m.points, tets)
    assert (vol > 0).all() and len(tets) == report["tetrahedra"]
    for tag in (3, 5, 7):
        assert (region == tag).sum() == by_tag[tag]["tetrahedra"]
        assert abs(vol[region == tag].sum() - by_tag[tag]["volume"]) < 1e-9 * by_tag[tag]["volume"]


@pytest.mark.parametrize("name", ["l.msh", "l22.msh"])
def test_meshio_reads_the_physical_groups_of_the_msh(labelled, name):
    d, _, report = labelled
    meshio = require("meshio", "python3-meshio")
    m = meshio.read(d / name)
    by_tag = {x["tag"]: x for x in report["materials"] if x["tetrahedra"] > 0}
    tets, tags = blocks(m, "tetra", "gmsh:physical")
    assert {int(t): int((tags == t).sum()) for t in np.unique(tags)} == {t: x["tetrahedra"] for t, x in by_tag.items()}
    tri, tri_tags = blocks(m, "triangle", "gmsh:physical")
    names = {k: int(v[0]) for k, v in m.field_data.items()}
    assert {f"label_{t}" for t in by_tag} <= set(names)
    interface_groups = [k for k in names if k.startswith("interface_")]
    assert sorted(interface_groups) == ["interface_3_5", "interface_3_7"]
    assert sum(int((tri_tags == names[k]).sum()) for k in interface_groups) == report["interface_faces"]
    assert (tri_tags == names["boundary"]).sum() == report["boundary_faces"]


def test_gmsh_reads_the_msh_with_its_physical_groups(labelled):
    d, _, report = labelled
    gmsh = require("gmsh", "python3-gmsh")
    r = subprocess.run(["gmsh", "-check", str(d / "l.msh")], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "Error" not in r.stdout + r.stderr, r.stdout + r.stderr
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(str(d / "l.msh"))
        groups = {gmsh.model.getPhysicalName(dim, tag): (dim, tag) for dim, tag in gmsh.model.getPhysicalGroups()}
        counts = {}
        for name, (dim, tag) in groups.items():
            n = 0
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                types, elements, _ = gmsh.model.mesh.getElements(dim, entity)
                assert list(types) == [4 if dim == 3 else 2], name
                n += len(elements[0])
            counts[name] = n
    finally:
        gmsh.finalize()
    expect = {f"label_{x['tag']}": x["tetrahedra"] for x in report["materials"] if x["tetrahedra"] > 0}
    assert {k: v for k, v in counts.items() if k.startswith("label_")} == expect
    assert counts["interface_3_5"] + counts["interface_3_7"] == report["interface_faces"]
    assert counts["boundary"] == report["boundary_faces"]


def test_xdmf_medit_and_inp_carry_the_regions_and_interfaces(labelled):
    d, _, report = labelled
    meshio = require("meshio", "python3-meshio")
    require("h5py", "python3-h5py")
    ref = meshio.read(d / "l.vtu")
    region = ref.cell_data["region"][0]
    x = meshio.read(d / "l.xdmf")
    assert np.array_equal(x.cells[0].data, ref.cells_dict["tetra"]) and np.array_equal(x.cell_data["region"][0], region)
    f = meshio.read(d / "l_facets.xdmf")
    names = {k: int(v[0]) for k, v in f.field_data.items()}
    tags = f.cell_data["facet_tags"][0]
    assert (tags == names["interface_3_5"]).sum() + (tags == names["interface_3_7"]).sum() == report["interface_faces"]
    medit = meshio.read(d / "l.mesh")
    tets, refs = blocks(medit, "tetra", "medit:ref")
    assert np.array_equal(tets, ref.cells_dict["tetra"]) and np.array_equal(refs, region)
    inp = meshio.read(d / "l.inp")
    for tag in (3, 5, 7):
        assert np.array_equal(np.sort(inp.cell_sets[f"label_{tag}"][0]), np.flatnonzero(region == tag))
    assert "interface_3_5" in inp.point_sets and "interface_3_7" in inp.point_sets


def test_units_voxel_size_and_memory_apply_to_materials(tmp_path):
    """--units pixels meshes in voxel indices (the 0.5 mm voxels' volumes
    x 8), --pixel-size overrides the header's voxel size, --max-memory
    refuses before meshing."""
    write_nrrd(tmp_path / "l.nrrd", labels_volume(), (0.5, 0.5, 0.5))
    runs = {"mm": ["--spacing", "1"], "px": ["--units", "pixels", "--spacing", "2"], "big": ["--pixel-size", "1", "--spacing", "2"]}
    reports = {}
    for name, args in runs.items():
        mesh3d(["l.nrrd", "--materials", "3,5", *args, "--report", f"{name}.json", "--quiet"], tmp_path)
        reports[name] = {m["tag"]: m for m in json.loads((tmp_path / f"{name}.json").read_text())["materials"]}
    for tag in (3, 5):
        mm, px, big = (reports[n][tag] for n in ("mm", "px", "big"))
        assert mm["voxels"] == px["voxels"] == big["voxels"]
        assert px["reference_volume"] == 8 * mm["reference_volume"] == big["reference_volume"]
        assert abs(px["volume"] / mm["volume"] - 8) < 1e-6 * 8 and abs(big["volume"] - px["volume"]) < 1e-6 * px["volume"]
    r = mesh3d(["l.nrrd", "--materials", "all", "--spacing", "0.01", "--max-memory", "1", "-o", "x.msh"], tmp_path, expect=1)
    assert "--max-memory" in r.stderr and not (tmp_path / "x.msh").exists()


def test_shapes_and_background_keep(tmp_path):
    """--shapes: analytic materials; --background keep adds the background
    (region 0; in .msh, whose tags are positive, the largest tag + 1, named
    "background")."""
    meshio = require("meshio", "python3-meshio")
    mesh3d(["--shapes", NESTED, "--spacing", "0.25", "-o", "d.vtu", "--report", "d.json", "--quiet"], tmp_path)
    mesh3d(["--shapes", NESTED, "--spacing", "0.25", "--background", "keep", "-o", "k.vtu", "--also", "k.msh",
            "--report", "k.json", "--quiet"], tmp_path)
    d, k = (json.loads((tmp_path / f"{n}.json").read_text()) for n in "dk")
    assert [m["tag"] for m in d["materials"]] == [1, 2] and [m["tag"] for m in k["materials"]] == [0, 1, 2]
    assert [m["tetrahedra"] for m in d["materials"]] == [m["tetrahedra"] for m in k["materials"][1:]]
    assert sorted(np.unique(meshio.read(tmp_path / "k.vtu").cell_data["region"][0])) == [0, 1, 2]
    msh = meshio.read(tmp_path / "k.msh")
    assert msh.field_data["background"][0] == 3
    assert abs(sum(m["volume"] for m in d["materials"]) - 4 / 3 * np.pi) < 0.05 * 4 / 3 * np.pi


@pytest.mark.parametrize("args, code, message", [
    (["l.nrrd", "--materials", "all", "--label", "3"], 2, "--materials (every label its own region) excludes"),
    (["l.nrrd", "--materials", "all", "--iso", "2"], 2, "excludes labels, iso and inside"),
    (["l.nrrd", "--materials", "3,x"], 2, "--materials expects all or a label list"),
    (["l.nrrd", "--materials", "0,3"], 1, "label 0 is the background"),
    (["l.nrrd", "--materials", "3,4"], 1, "not present in the volume: 4"),
    (["l.nrrd", "--materials", "all", "--face-rule", "delaunay"], 2, "--face-rule delaunay is not available with several"),
    (["l.nrrd", "--label", "3", "--background", "keep"], 2, "--background applies to several materials"),
    (["--shape", "sphere:0,0,0,1", "--spacing", "0.3", "--materials", "all"], 2, "materials apply to volumes"),
    (["--shapes", NESTED], 2, "spacing is required"),
    (["--shapes", NESTED, "l.nrrd", "--spacing", "0.3"], 2, "give exactly one of an input volume, --shape SPEC or --shapes"),
    (["--shapes", "1=sphere:0,0,0,1;1=sphere:0,0,0,2", "--spacing", "0.3"], 1, "tag 1 is given twice"),
    (["--shapes", "1=sphere:0,0,0,1", "--spacing", "0.3", "--iso", "1"], 2, "apply to volumes"),
])
def test_bad_input_is_refused_with_a_message_and_nothing_written(tmp_path, args, code, message):
    write_nrrd(tmp_path / "l.nrrd", labels_volume())
    r = mesh3d([*args, "-o", "x.msh", "--report", "x.json"], tmp_path, expect=code)
    assert message in r.stderr, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["l.nrrd"]


def test_help_describes_the_materials():
    r = subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--help"], capture_output=True, text=True, check=True)
    assert "--materials all|L,L,..." in r.stdout and "--shapes \"T=S;T=S\"" in r.stdout
    assert "proofs/bcc_junctions.cert where 3 or 4 meet" in r.stdout and "--background drop|keep" in r.stdout


# ---- CalculiX: three materials in series -------------------------------------------

# A bar [0, 3] x [0, 1] x [0, 1] of three materials in series (tag 1 on x < 1,
# 2 on 1 < x < 2, 3 on x > 2): clamped at x = 0 (NSET FIXED, from the mesh),
# pulled at x = 3 (NSET END, a total force of 1 along x).
BAR = "1=box:0,0,0,3,1,1;2=box:1,0,0,2,1,1;3=box:2,0,0,3,1,1"
CALCULIX_DECK = """*INCLUDE, INPUT=bar.inp
*NSET, NSET=FIXED
{fixed}
*NSET, NSET=END
{end}
*MATERIAL, NAME=SOFT
*ELASTIC
1000., 0.3
*MATERIAL, NAME=MEDIUM
*ELASTIC
10000., 0.3
*MATERIAL, NAME=STIFF
*ELASTIC
100000., 0.3
*SOLID SECTION, ELSET=material_1, MATERIAL=SOFT
*SOLID SECTION, ELSET=material_2, MATERIAL=MEDIUM
*SOLID SECTION, ELSET=material_3, MATERIAL=STIFF
*BOUNDARY
FIXED, 1, 3, 0.
*STEP
*STATIC
*CLOAD
{load}
*NODE PRINT, NSET=INTERFACE_1_2
U
*NODE PRINT, NSET=END
U
*END STEP
"""


def node_list(nodes):
    """Abaqus node numbers (1-based), 8 a line."""
    ids = [str(int(n) + 1) for n in nodes]
    return "\n".join(", ".join(ids[k:k + 8]) for k in range(0, len(ids), 8))


def test_calculix_solves_a_three_material_bar(tmp_path):
    """CalculiX reads the .inp of a three-material mesh, gives each material's
    *ELSET its own Young's modulus and solves: the displacements are finite,
    the pulled end moves along +x by about F (1/E1 + 1/E2 + 1/E3) (springs in
    series, the clamp's restraint of the contraction aside), and most of it
    is the soft material's: the interface between materials 1 and 2 has
    moved about 0.9 of the end's displacement."""
    meshio = require("meshio", "python3-meshio")
    mesh3d(["--shapes", BAR, "--spacing", "0.2", "-o", "bar.inp", "--also", "bar.vtu", "--quiet"], tmp_path)
    p = meshio.read(tmp_path / "bar.vtu").points
    fixed = np.flatnonzero(p[:, 0] < 1e-9)
    end = np.flatnonzero(p[:, 0] > 3 - 1e-9)
    assert len(fixed) > 10 and len(end) > 10
    load = "\n".join(f"{n + 1}, 1, {1 / len(end)!r}" for n in end)
    printed = run_calculix(tmp_path, CALCULIX_DECK.format(fixed=node_list(fixed), end=node_list(end), load=load))
    end_u = np.array(list(printed["END"].values()))
    interface_u = np.array(list(printed["INTERFACE_1_2"].values()))
    assert len(end_u) == len(end) and len(interface_u) > 10
    assert np.isfinite(end_u).all() and np.isfinite(interface_u).all()
    series = 1 / 1000 + 1 / 10000 + 1 / 100000
    assert 0.7 * series < end_u[:, 0].mean() < 1.1 * series, end_u[:, 0].mean()
    assert 0.8 < interface_u[:, 0].mean() / end_u[:, 0].mean() < 0.97


def test_graded_labels_keep_the_uniform_interfaces_and_volumes(labelled):
    """--materials all --graded (issue 48): every interface and the boundary
    stay at the finest level, so the boundary and interface faces and every
    label's volume are the uniform mesh's, with fewer tetrahedra, each
    positive (meshio), tagged with its label and verified."""
    d = labelled[0]
    meshio = require("meshio", "python3-meshio")
    args = ["l.nrrd", "--materials", "all", "--spacing", "0.5", "--verify", "--quiet"]
    mesh3d([*args, "-o", "u.vtu", "--report", "u.json"], d)
    mesh3d([*args, "--graded", "-o", "g.vtu", "--report", "g.json"], d)
    u, g = (json.loads((d / f"{n}.json").read_text()) for n in ("u", "g"))
    assert g["tetrahedra"] < u["tetrahedra"] and g["graded"]["template_tetrahedra"] > 0
    assert g["boundary_faces"] == u["boundary_faces"] and g["interface_faces"] == u["interface_faces"] > 0
    assert g["certified"]["verified"] and g["certified"]["uncertified_tetrahedra"] == 0
    assert [x["tag"] for x in g["materials"]] == [x["tag"] for x in u["materials"]]
    for a, b in zip(u["materials"], g["materials"]):
        assert abs(a["volume"] - b["volume"]) <= 1e-9 * a["volume"], a["tag"]
    m = meshio.read(d / "g.vtu")
    tets, region = m.cells_dict["tetra"], m.cell_data["region"][0]
    vol = tet_volumes(m.points, tets)
    assert (vol > 0).all() and len(tets) == g["tetrahedra"]
    for x in g["materials"]:
        assert abs(vol[region == x["tag"]].sum() - x["volume"]) <= 1e-9 * max(x["volume"], 1e-300)
