"""Round trips through the solvers' own readers: what warpmesh writes in .msh
(4.1, 2.2, with and without cell data), .vtu, .xdmf and .inp is read back with
meshio, gmsh (its command line and its Python API) and dolfinx, and the points,
triangles, region tags, boundary/interface tags and group names are compared
with the Triangle files (.node/.ele/.poly) that warpmesh wrote in the same run.

Cases: the unit disc from --shape (one region, boundary tag 1), a thresholded
image whose object is cut off by the image border (tags 1 and 2), and the
hand-built two-region mesh with interfaces (tests/fixture_meshes.hpp), whose regions are 3 ("left material")
and 8 (unnamed, "domain_8") and whose interface facets are tagged 3; and a
graded multi-material mesh of two analytic materials from the CLI
(--shapes ... --graded: interfaces tagged 3, coarse leaves inside).
"""
import os
import subprocess

import numpy as np
import pytest

from conftest import (Reference, executable, require, run_calculix, run_warpmesh, tagged_cells, tagged_edges,
                      write_pgm)

# Files of one case: STEM.node/.ele/.poly (the reference), STEM.msh (4.1),
# STEM-22.msh (2.2), STEM-data.msh (4.1 with cell data), STEM.vtu,
# STEM.xdmf (+ STEM_facets.xdmf, heavy data in STEM.h5 and STEM_facets.h5),
# STEM.inp: binary where the format has it (the default); STEM-ascii.msh,
# STEM-22-ascii.msh, STEM-ascii.vtu, STEM-ascii.xdmf (inline XML): --ascii;
# STEM-z.vtu: --compress (zlib).
CASES = {
    "disc": {
        "args": ["--shape", "circle:0,0,1", "--spacing", "0.15"],
        "regions": {1: "domain"},
        "facets": {1: "boundary"},
    },
    "cut": {
        "args": ["cut.pgm", "--spacing", "1.5"],
        "regions": {1: "domain"},
        "facets": {1: "boundary", 2: "domain_border"},
    },
    # A graded multi-material mesh: a disc inside a disc (no triple point, so
    # no junction square: every triangle has a certified bound), the
    # background dropped; coarse leaves inside both materials.
    "graded_materials": {
        "args": ["--shapes", "1=circle:0,0,3;2=circle:0.5,0,1.5", "--graded", "--spacing", "0.125"],
        "regions": {1: "material_1", 2: "material_2"},
        "facets": {1: "boundary", 3: "interface_1_2"},
    },
    "two": {
        "regions": {3: "left material", 8: "domain_8"},
        "facets": {1: "boundary", 2: "domain_border", 3: "interface_3_8"},
    },
}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request, tmp_path_factory, two_region):
    name = request.param
    spec = CASES[name]
    if name == "two":
        return name, two_region, spec
    d = tmp_path_factory.mktemp(name)
    if name == "cut":
        # A bright disc of radius 12 centred 4 px from the right border of a
        # 40 x 30 image: the region is cut off there (domain_border).
        y, x = np.mgrid[0:30, 0:40]
        write_pgm(d / "cut.pgm", np.where((x - 36) ** 2 + (y - 15) ** 2 < 144, 220, 20))
    stem = str(d / name)
    args = spec["args"]
    run_warpmesh([*args, "-o", stem + ".node", "--also", stem + ".msh", "--also", stem + ".vtu",
                  "--also", stem + ".xdmf", "--also", stem + ".inp"], d)
    run_warpmesh([*args, "-o", stem + "-22.msh", "--msh-version", "2.2"], d)
    # The text forms of the binary formats (--ascii) and the zlib .vtu.
    run_warpmesh([*args, "-o", stem + "-ascii.msh", "--also", stem + "-ascii.vtu", "--also", stem + "-ascii.xdmf",
                  "--ascii"], d)
    run_warpmesh([*args, "-o", stem + "-22-ascii.msh", "--msh-version", "2.2", "--ascii"], d)
    run_warpmesh([*args, "-o", stem + "-z.vtu", "--compress"], d)
    run_warpmesh([*args, "-o", stem + "-data.msh", "--msh-cell-data", "--also", stem + "-data.vtu"], d)
    return name, stem, spec


def test_cases_cover_every_tag(case):
    # Guards the fixtures themselves: each case has the tags it claims.
    name, stem, spec = case
    ref = Reference(stem)
    assert set(np.unique(ref.region)) == set(spec["regions"])
    assert set(np.unique(ref.segment_tags)) == set(spec["facets"])


def check_points(points, ref, rtol=0):
    """Same coordinates, bit for bit (every writer prints round-trip decimals;
    .inp rounds numbers longer than CalculiX's 20 characters: rtol)."""
    points = np.asarray(points, dtype=float)
    assert points.shape[0] == len(ref.points)
    if rtol:
        assert np.allclose(points[:, :2], ref.points, rtol=rtol, atol=0)
    else:
        assert np.array_equal(points[:, :2], ref.points)
    if points.shape[1] == 3:
        assert not points[:, 2].any()


def check_triangle_mesh(m, ref, rtol=0):
    """A meshio mesh of one triangle block: the reference's points and
    triangles, in the reference's order."""
    check_points(m.points, ref, rtol)
    assert [c.type for c in m.cells] == ["triangle"]
    assert np.array_equal(m.cells[0].data, ref.triangles)


def field_names(m):
    """meshio's field_data as {name: [tag, dim]}."""
    return {k: [int(v[0]), int(v[1])] for k, v in m.field_data.items()}


def check_boundary_orientation(edges, tags, ref, spec):
    """Boundary lines keep the mesh's orientation (region on the left)."""
    boundary = {tuple(int(v) for v in e) for e, t in zip(ref.segments, ref.segment_tags)
                if not spec["facets"][int(t)].startswith("interface")}
    for e, t in zip(edges, tags):
        if not spec["facets"][int(t)].startswith("interface"):
            assert tuple(int(v) for v in e) in boundary


# ---- meshio --------------------------------------------------------------------

def meshio_blocks(m, cell_type, key):
    cells = [c.data for c in m.cells if c.type == cell_type]
    tags = [d for c, d in zip(m.cells, m.cell_data[key]) if c.type == cell_type]
    if not cells:
        return np.zeros((0, 3 if cell_type == "triangle" else 2), dtype=int), np.zeros(0, dtype=int)
    return np.concatenate(cells), np.concatenate(tags)


MSH_FORMS = ["", "-22", "-data", "-ascii", "-22-ascii"]


@pytest.mark.parametrize("suffix", MSH_FORMS)
def test_meshio_reads_msh_with_named_physical_groups(case, suffix):
    meshio = require("meshio", "python3-meshio")
    name, stem, spec = case
    ref = Reference(stem)
    m = meshio.read(stem + suffix + ".msh")
    check_points(m.points, ref)
    assert {c.type for c in m.cells} == {"triangle", "line"}
    tri, tri_tags = meshio_blocks(m, "triangle", "gmsh:physical")
    assert tagged_cells(tri, tri_tags) == ref.tagged_triangles()
    lines, line_tags = meshio_blocks(m, "line", "gmsh:physical")
    assert tagged_edges(lines, line_tags) == ref.tagged_edges()
    check_boundary_orientation(lines, line_tags, ref, spec)
    # Entity tags equal physical tags.
    assert np.array_equal(meshio_blocks(m, "triangle", "gmsh:geometrical")[1], tri_tags)
    # Names: meshio's field_data is {name: [tag, dim]}.
    expect = {n: [t, 2] for t, n in spec["regions"].items()}
    expect.update({n: [t, 1] for t, n in spec["facets"].items()})
    assert field_names(m) == expect
    data_names = set(m.cell_data) - {"gmsh:physical", "gmsh:geometrical"}
    if suffix != "-data":
        assert not data_names, "per-triangle data in a .msh nobody asked for"


def test_meshio_reads_msh_cell_data_on_every_element(case):
    meshio = require("meshio", "python3-meshio")
    name, stem, spec = case
    m = meshio.read(stem + "-data.msh")
    assert "certified_min_angle" in m.cell_data
    by_block = dict(zip([c.type for c in m.cells], m.cell_data["certified_min_angle"]))
    tri_values = np.concatenate([d for c, d in zip(m.cells, m.cell_data["certified_min_angle"]) if c.type == "triangle"])
    line_values = np.concatenate([d for c, d in zip(m.cells, m.cell_data["certified_min_angle"]) if c.type == "line"])
    assert by_block and np.isnan(line_values).all()
    if name == "two":
        return  # hand-made values, checked in test_writers.cpp
    assert np.isfinite(tri_values).all() and (tri_values > 0).all() and (tri_values <= 60).all()
    # The same values, triangle by triangle, as the .vtu of the same run.
    vtu = meshio.read(stem + "-data.vtu")
    tri, _ = meshio_blocks(m, "triangle", "gmsh:physical")
    want = {tuple(t): v for t, v in zip(vtu.cells_dict["triangle"].tolist(), vtu.cell_data["certified_min_angle"][0])}
    assert all(want[tuple(t)] == v for t, v in zip(tri.tolist(), tri_values))


@pytest.mark.parametrize("suffix", ["", "-z", "-ascii"])
def test_meshio_reads_vtu(case, suffix):
    meshio = require("meshio", "python3-meshio")
    name, stem, spec = case
    ref = Reference(stem)
    m = meshio.read(stem + suffix + ".vtu")
    check_triangle_mesh(m, ref)
    assert np.array_equal(m.cell_data["region"][0], ref.region)
    assert np.array_equal(m.point_data["boundary_marker"], ref.markers)


@pytest.mark.parametrize("suffix", ["", "-ascii"])
def test_meshio_reads_xdmf_mesh_and_facets(case, suffix):
    meshio = require("meshio", "python3-meshio")
    require("h5py", "python3-h5py")  # meshio's XDMF reader imports it even for inline XML
    name, stem, spec = case
    ref = Reference(stem)
    stem = stem + suffix
    m = meshio.read(stem + ".xdmf")
    check_triangle_mesh(m, ref)
    assert np.array_equal(m.cell_data["region"][0], ref.region)
    assert field_names(m) == {n: [t, 2] for t, n in spec["regions"].items()}
    f = meshio.read(stem + "_facets.xdmf")
    check_points(f.points, ref)
    assert [c.type for c in f.cells] == ["line"]
    assert tagged_edges(f.cells[0].data, f.cell_data["facet_tags"][0]) == ref.tagged_edges()
    check_boundary_orientation(f.cells[0].data, f.cell_data["facet_tags"][0], ref, spec)
    assert field_names(f) == {n: [t, 1] for t, n in spec["facets"].items()}


def abaqus_name(name):
    return "".join(c if c.isalnum() or c == "_" else "_" for c in name)


def test_meshio_reads_abaqus_inp_with_sets(case):
    meshio = require("meshio", "python3-meshio")
    name, stem, spec = case
    ref = Reference(stem)
    m = meshio.read(stem + ".inp")
    check_triangle_mesh(m, ref, rtol=5e-14)
    # One element set per region: exactly the region's triangles.
    for tag, region in spec["regions"].items():
        got = m.cell_sets[abaqus_name(region)][0]
        assert np.array_equal(np.sort(got), np.flatnonzero(ref.region == tag))
    # One node set per facet group: the nodes of its edges.
    for tag, group in spec["facets"].items():
        want = np.unique(ref.segments[ref.segment_tags == tag])
        assert np.array_equal(np.sort(m.point_sets[group]), want)
    # The element-face sets behind each *SURFACE: face Sk of element e is the
    # edge (n_k, n_k+1) of its triangle; together they are the group's edges.
    for tag, group in spec["facets"].items():
        faces = set()
        for side in (1, 2, 3):
            key = f"_{group}_S{side}"
            if key in m.cell_sets:
                for e in m.cell_sets[key][0]:
                    t = ref.triangles[e]
                    faces.add(frozenset((int(t[side - 1]), int(t[side % 3]))))
        assert faces == {k for k, v in ref.tagged_edges().items() if v == tag}


# ---- gmsh ----------------------------------------------------------------------

@pytest.mark.parametrize("suffix", MSH_FORMS)
def test_gmsh_check_accepts_msh(case, suffix):
    name, stem, spec = case
    r = subprocess.run(["gmsh", "-check", stem + suffix + ".msh"], capture_output=True, text=True, timeout=60)
    out = r.stdout + r.stderr
    assert r.returncode == 0, out
    assert "Error" not in out, out
    ref = Reference(stem)
    assert f"{len(ref.points)} nodes" in out, out


@pytest.mark.parametrize("suffix", ["", "-22", "-ascii", "-22-ascii"])
def test_gmsh_api_reads_named_physical_groups(case, suffix):
    gmsh = require("gmsh", "python3-gmsh")
    name, stem, spec = case
    ref = Reference(stem)
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(stem + suffix + ".msh")
        tags, coords, _ = gmsh.model.mesh.getNodes()
        order = np.argsort(tags)
        assert np.array_equal(tags[order], np.arange(1, len(ref.points) + 1))
        check_points(coords.reshape(-1, 3)[order], ref)
        groups = {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        expect = {(2, t): n for t, n in spec["regions"].items()}
        expect.update({(1, t): n for t, n in spec["facets"].items()})
        assert groups == expect
        triangles, edges = {}, {}
        for (dim, tag) in groups:
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                types, _, nodes = gmsh.model.mesh.getElements(dim, entity)
                assert list(types) == [2 if dim == 2 else 1]
                cells = nodes[0].reshape(-1, 3 if dim == 2 else 2).astype(np.int64) - 1
                (triangles if dim == 2 else edges).update(
                    tagged_cells(cells, [tag] * len(cells)) if dim == 2 else tagged_edges(cells, [tag] * len(cells)))
        assert triangles == ref.tagged_triangles()
        assert edges == ref.tagged_edges()
    finally:
        gmsh.finalize()


# ---- dolfinx -------------------------------------------------------------------

def dolfinx_tags(mesh, tags, ref_index):
    """{frozenset of reference vertex ids: tag} for the entities of `tags`."""
    cpp = require("dolfinx.cpp", "python3-dolfinx")
    original = np.asarray(mesh.geometry.input_global_indices)
    # dolfinx 0.5: the C++ mesh behind the Python one is mesh._mesh.
    nodes = cpp.mesh.entities_to_geometry(mesh._mesh, tags.dim, tags.indices, False)
    out = {frozenset(int(original[v]) for v in e): int(t) for e, t in zip(nodes, tags.values)}
    assert len(out) == len(tags.indices)
    return out


def dolfinx_cells(mesh):
    """{frozenset of reference vertex ids} of every cell, and the coordinates
    by reference vertex id."""
    original = np.asarray(mesh.geometry.input_global_indices)
    x = np.empty((len(original), 2))
    x[original] = mesh.geometry.x[:, :2]
    cells = mesh.geometry.dofmap.array.reshape(-1, 3)
    return {frozenset(int(original[v]) for v in c) for c in cells}, x


def check_dolfinx(mesh, cell_tags, facet_tags, ref):
    cells, x = dolfinx_cells(mesh)
    assert np.array_equal(x, ref.points)
    assert cells == {frozenset(t) for t in ref.triangles.tolist()}
    assert dolfinx_tags(mesh, cell_tags, ref) == {frozenset(k): v for k, v in ref.tagged_triangles().items()}
    assert dolfinx_tags(mesh, facet_tags, ref) == ref.tagged_edges()


@pytest.mark.parametrize("suffix", ["", "-ascii"])
def test_dolfinx_reads_xdmf_mesh_cell_and_facet_tags(case, suffix):
    """The HDF5 form (the default, as dolfinx itself writes XDMF) and the
    inline-XML form (--ascii)."""
    require("dolfinx", "python3-dolfinx")
    from mpi4py import MPI
    from dolfinx.io import XDMFFile
    name, stem, spec = case
    ref = Reference(stem)
    encoding = XDMFFile.Encoding.ASCII if suffix else XDMFFile.Encoding.HDF5
    with XDMFFile(MPI.COMM_WORLD, stem + suffix + ".xdmf", "r", encoding=encoding) as f:
        mesh = f.read_mesh(name="mesh")
        cell_tags = f.read_meshtags(mesh, name="mesh")
    assert mesh.geometry.dim == 2 and mesh.topology.dim == 2
    mesh.topology.create_connectivity(1, 2)
    with XDMFFile(MPI.COMM_WORLD, stem + suffix + "_facets.xdmf", "r", encoding=encoding) as f:
        facet_tags = f.read_meshtags(mesh, name="facets")
    check_dolfinx(mesh, cell_tags, facet_tags, ref)


@pytest.mark.parametrize("suffix", ["", "-22"])
def test_dolfinx_gmshio_reads_msh(case, suffix):
    require("dolfinx", "python3-dolfinx")
    gmsh = require("gmsh", "python3-gmsh")
    from mpi4py import MPI
    from dolfinx.io import gmshio
    name, stem, spec = case
    ref = Reference(stem)
    # dolfinx 0.5.2's gmshio.read_from_msh is broken (it finalizes gmsh and
    # returns an undefined name); model_to_mesh on a merged model is the path
    # its demos use.
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.merge(stem + suffix + ".msh")
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=2)
    finally:
        gmsh.finalize()
    check_dolfinx(mesh, cell_tags, facet_tags, ref)


# ---- VTK -----------------------------------------------------------------------

@pytest.mark.parametrize("suffix", ["", "-z", "-ascii"])
def test_vtk_reads_binary_zlib_and_ascii_vtu(case, suffix):
    """VTK's own XML reader (not meshio's parser) on the appended raw binary,
    the zlib-compressed and the ASCII .vtu."""
    vtk = require("vtk", "python3-vtk9")
    from vtk.util.numpy_support import vtk_to_numpy
    name, stem, spec = case
    ref = Reference(stem)
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(stem + suffix + ".vtu")
    r.Update()
    assert r.GetErrorCode() == 0
    g = r.GetOutput()
    assert np.array_equal(vtk_to_numpy(g.GetPoints().GetData())[:, :2], ref.points)
    assert np.array_equal(vtk_to_numpy(g.GetCellTypesArray()), np.full(len(ref.triangles), 5))
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 3)
    assert np.array_equal(conn, ref.triangles)
    assert np.array_equal(vtk_to_numpy(g.GetCellData().GetArray("region")), ref.region)
    assert np.array_equal(vtk_to_numpy(g.GetPointData().GetArray("boundary_marker")), ref.markers)


# ---- Triangle ------------------------------------------------------------------

def test_node_markers_carry_the_poly_tags(case):
    """A boundary vertex is marked with its boundary edges' tag (the smallest
    if two meet), an interface vertex with the interface's, others 0."""
    name, stem, spec = case
    ref = Reference(stem)
    boundary, interface = {}, {}
    for (a, b), t in zip(ref.segments.tolist(), ref.segment_tags.tolist()):
        d = interface if spec["facets"][t].startswith("interface") else boundary
        for v in (a, b):
            d[v] = min(d.get(v, t), t)
    want = [boundary.get(v, interface.get(v, 0)) for v in range(len(ref.points))]
    assert ref.markers.tolist() == want
    assert set(ref.markers.tolist()) - {0} == set(spec["facets"])


# ---- CalculiX (Abaqus input) ---------------------------------------------------

CALCULIX_DECK = """*INCLUDE, INPUT=two.inp
*MATERIAL, NAME=SOFT
*ELASTIC
1000., 0.3
*MATERIAL, NAME=STIFF
*ELASTIC
10000., 0.3
*SOLID SECTION, ELSET=left_material, MATERIAL=SOFT
0.1
*SOLID SECTION, ELSET=domain_8, MATERIAL=STIFF
0.1
*BOUNDARY
domain_border, 1, 2, 0.
*STEP
*STATIC
*DSLOAD
boundary, P, 1.
*NODE PRINT, NSET=domain_border
U
*NODE PRINT, NSET=interface_3_8
U
*END STEP
"""


def test_calculix_solves_with_the_inp_sets_and_surfaces(two_region, tmp_path):
    """CalculiX (ccx), an Abaqus-format solver, reads the .inp, puts a material
    on each region's *ELSET, clamps the *NSET domain_border (left and right
    sides) and pushes with a pressure on the *SURFACE boundary (bottom and top
    edges, as element faces).  Pressure acts into the body, so where the
    interface meets the bottom the material moves up and at the top down —
    faces on the wrong side of their edges would pull instead."""
    import shutil
    shutil.copy(two_region + ".inp", tmp_path / "two.inp")
    printed = run_calculix(tmp_path, CALCULIX_DECK)
    ref = Reference(two_region)
    assert set(printed["DOMAIN_BORDER"]) == set(np.unique(ref.segments[ref.segment_tags == 2]).tolist())
    assert all(u == [0.0, 0.0, 0.0] for u in printed["DOMAIN_BORDER"].values())
    interface = printed["INTERFACE_3_8"]
    assert set(interface) == set(np.unique(ref.segments[ref.segment_tags == 3]).tolist())
    bottom = min(interface, key=lambda v: ref.points[v, 1])
    top = max(interface, key=lambda v: ref.points[v, 1])
    assert interface[bottom][1] > 0 > interface[top][1]


# ---- region tags across formats (issue 27 item 5) ------------------------------

def test_background_keep_tags_are_the_labels_in_every_format(tmp_path):
    """With --background keep, .msh renumbered the regions (background 1,
    label_5 2, …) while the other formats kept the labels.  Now every format
    tags a label's triangles with the label value; the background is 0, and in
    .msh (whose tags must be positive) the largest label + 1, named
    "background"."""
    meshio = require("meshio", "python3-meshio")
    pixels = np.zeros((12, 12), dtype=np.uint8)
    pixels[2:7, 2:9] = 5
    pixels[6:10, 4:8] = 7
    write_pgm(tmp_path / "l.pgm", pixels)
    outs = ["k.msh", "k.vtu", "k.xdmf", "k.ele", "k-ascii.msh", "k.inp"]
    run_warpmesh(["l.pgm", "--materials", "all", "--background", "keep", "--spacing", "0.5", "-o", "k.vtu",
                  *[a for o in outs if o != "k.vtu" and o != "k-ascii.msh" for a in ("--also", o)]], tmp_path)
    run_warpmesh(["l.pgm", "--materials", "all", "--background", "keep", "--spacing", "0.5", "-o", "k-ascii.msh",
                  "--ascii"], tmp_path)
    ref = Reference(str(tmp_path / "k"))
    assert set(np.unique(ref.region)) == {0, 5, 7}
    for f in ["k.vtu", "k.xdmf"]:
        m = meshio.read(tmp_path / f)
        assert np.array_equal(m.cell_data["region"][0], ref.region), f
    for f in ["k.msh", "k-ascii.msh"]:
        m = meshio.read(tmp_path / f)
        tri, tags = meshio_blocks(m, "triangle", "gmsh:physical")
        want = {k: (8 if v == 0 else v) for k, v in ref.tagged_triangles().items()}
        assert tagged_cells(tri, tags) == want, f
        names = field_names(m)
        assert names["label_5"] == [5, 2] and names["label_7"] == [7, 2] and names["background"] == [8, 2], f
    inp = (tmp_path / "k.inp").read_text()
    for name in ["background", "label_5", "label_7"]:
        assert f"*ELSET, ELSET={name}\n" in inp


def test_slices_write_hdf5_xdmf_in_parallel(tmp_path):
    """--slices writes its outputs from several threads; the serial HDF5
    library is not thread-safe, so write_xdmf serialises its .h5 writes.  Each
    slice's four files appear, named by the final names, and read back."""
    meshio = require("meshio", "python3-meshio")
    z, y, x = np.mgrid[0:6, 0:40, 0:40]
    v = ((((x - 20) ** 2 + (y - 20) ** 2) < (10 + z) ** 2) * 200).astype("<u2")
    (tmp_path / "v.nrrd").write_bytes(b"NRRD0004\ntype: unsigned short\ndimension: 3\nsizes: 40 40 6\n"
                                      b"encoding: raw\nendian: little\n\n" + v.tobytes())
    r = subprocess.run([executable("WARPMESH_EXE"), "mesh", "v.nrrd", "--slices", "k=0:6", "--iso", "100",
                        "--spacing", "0.5", "--units", "pixels", "-o", "s%d.xdmf", "--threads", "2", "--quiet"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=120, env={**os.environ, "OMP_NUM_THREADS": "2"})
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []
    counts = []
    for i in range(6):
        assert (tmp_path / f"s{i}.h5").exists() and (tmp_path / f"s{i}_facets.h5").exists()
        assert f">s{i}.h5:/mesh/topology<" in (tmp_path / f"s{i}.xdmf").read_text()
        counts.append(len(meshio.read(tmp_path / f"s{i}.xdmf").cells[0]))
        assert len(meshio.read(tmp_path / f"s{i}_facets.xdmf").cells[0]) > 0
    assert counts == sorted(counts) and counts[0] < counts[-1]  # the disc grows with k


@pytest.mark.parametrize("extra", [[], ["--compress"]])
def test_issue32_meshio_offset_shadow(tmp_path, extra):
    """meshio 5 reads appended .vtu data by rewriting each DataArray's offset
    as it goes and finding the next array by offset in document order; with
    the arrays appended in document order, this 5-point mesh's rewritten
    connectivity offset (172) shadowed the raw offset of "offsets" (172) and
    meshio raised ReadError (found by scripts/stress.sh).  The writer appends
    the arrays in reverse document order; meshio and VTK read both forms."""
    import meshio
    vtk = require("vtk", "python3-vtk9")
    data = os.path.join(os.path.dirname(__file__), "..", "data", "issue32_meshio_offset_shadow.pgm")
    out = tmp_path / "out.vtu"
    run_warpmesh([data, "--iso", "209.201", "--spacing", "1.3489", "--graded", "--max-size", "4.559",
                  "--diagonal", "fan", "-o", out, *extra], tmp_path)
    m = meshio.read(out)
    assert len(m.points) == 5 and len(m.cells_dict["triangle"]) == 3
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(out))
    r.Update()
    assert r.GetErrorCode() == 0 and r.GetOutput().GetNumberOfCells() == 3
