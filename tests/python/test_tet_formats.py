"""Round trips of tetrahedral meshes through the solvers' own readers (issue
30, item 4): the hand-built tetrahedral fixture (tests/fixture_meshes.hpp,
cube_tet_mesh: 4 x 2 x 3 cubes of 6 Kuhn tetrahedra, regions 3 "left
material" and 8, boundary tags 1 and 2, interface triangles tagged 3),
written by the library's writers in .vtu, .msh 4.1/2.2, .xdmf + HDF5, .inp
and medit .mesh (binary and text forms), is read back with meshio, gmsh
(command line and Python API), dolfinx, VTK and CalculiX and compared with
the reference the fixture tool wrote directly (cubes.ref).
"""
import os
import shutil
import subprocess

import numpy as np
import pytest

from conftest import require, write_fixtures

REGIONS = {3: "left material", 8: "domain_8"}
FACETS = {1: "boundary", 2: "domain_border", 3: "interface_3_8"}


class TetReference:
    """cubes.ref: points (N, 3), tets (T, 4) with region (T,), facets (F, 3)
    oriented outwards (interfaces out of region 3) with facet_tags (F,)."""

    def __init__(self, stem):
        with open(stem + ".ref") as f:
            lines = [ln.split() for ln in f]
        at = 0

        def section(name, convert):
            nonlocal at
            assert lines[at][0] == name
            n = int(lines[at][1])
            rows = [[convert(v) for v in r] for r in lines[at + 1:at + 1 + n]]
            at += n + 1
            return rows

        self.points = np.array(section("points", float))
        tets = np.array(section("tets", int), dtype=np.int64)
        self.tets, self.region = tets[:, :4], tets[:, 4]
        facets = np.array(section("facets", int), dtype=np.int64)
        self.facets, self.facet_tags = facets[:, :3], facets[:, 3]

    def markers(self):
        """The smallest boundary tag at a vertex, else the interface's, else 0."""
        boundary, interface = {}, {}
        for f, t in zip(self.facets.tolist(), self.facet_tags.tolist()):
            d = interface if t == 3 else boundary
            for v in f:
                d[v] = min(d.get(v, t), t)
        return np.array([boundary.get(v, interface.get(v, 0)) for v in range(len(self.points))])


def oriented(f):
    """A triangle as a tuple from its smallest vertex, orientation kept."""
    f = [int(v) for v in f]
    k = f.index(min(f))
    return tuple(f[k:] + f[:k])


def tagged_facets(facets, tags):
    d = {oriented(f): int(t) for f, t in zip(facets, tags)}
    assert len(d) == len(facets), "a triangle appears twice"
    return d


def tagged_tets(tets, tags):
    d = {tuple(int(v) for v in t): int(g) for t, g in zip(tets, tags)}
    assert len(d) == len(tets)
    return d


@pytest.fixture(scope="module")
def cubes(tmp_path_factory):
    stem = os.path.join(os.path.dirname(write_fixtures(tmp_path_factory.mktemp("tets"))), "cubes")
    return stem, TetReference(stem)


def test_fixture_is_positive_and_closed(cubes):
    """Guards the fixture: positive tetrahedra, a closed outward boundary
    (the divergence theorem: the outward area vectors sum to zero, and the
    volume from the boundary equals the tetrahedra's)."""
    _, ref = cubes
    p = ref.points
    a, b, c, d = (p[ref.tets[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6
    assert (vol > 0).all()
    bnd = ref.facets[ref.facet_tags != 3]
    x, y, z = (p[bnd[:, k]] for k in range(3))
    n = np.cross(y - x, z - x)
    assert np.allclose(n.sum(axis=0), 0, atol=1e-12)
    assert np.isclose(np.einsum("ij,ij->", x, n) / 6, vol.sum())
    assert set(ref.facet_tags.tolist()) == set(FACETS) and set(ref.region.tolist()) == set(REGIONS)


# ---- meshio --------------------------------------------------------------------

def blocks(m, cell_type, key):
    data = [c.data for c in m.cells if c.type == cell_type]
    tags = [d for c, d in zip(m.cells, m.cell_data[key]) if c.type == cell_type]
    return np.concatenate(data), np.concatenate(tags)


def field_names(m):
    return {k: [int(v[0]), int(v[1])] for k, v in m.field_data.items()}


@pytest.mark.parametrize("suffix", ["", "-22", "-data", "-ascii", "-22-ascii"])
def test_meshio_reads_msh(cubes, suffix):
    meshio = require("meshio", "python3-meshio")
    stem, ref = cubes
    m = meshio.read(stem + suffix + ".msh")
    assert np.array_equal(m.points, ref.points)
    assert {c.type for c in m.cells} == {"tetra", "triangle"}
    tets, tags = blocks(m, "tetra", "gmsh:physical")
    assert tagged_tets(tets, tags) == tagged_tets(ref.tets, ref.region)
    tri, tri_tags = blocks(m, "triangle", "gmsh:physical")
    assert tagged_facets(tri, tri_tags) == tagged_facets(ref.facets, ref.facet_tags)
    expect = {n: [t, 3] for t, n in REGIONS.items()}
    expect.update({n: [t, 2] for t, n in FACETS.items()})
    assert field_names(m) == expect
    if suffix == "-data":
        values = np.concatenate([d for c, d in zip(m.cells, m.cell_data["min_dihedral"]) if c.type == "tetra"])
        assert np.isfinite(values).all()


@pytest.mark.parametrize("suffix", ["", "-z", "-ascii"])
def test_meshio_reads_vtu(cubes, suffix):
    meshio = require("meshio", "python3-meshio")
    stem, ref = cubes
    m = meshio.read(stem + suffix + ".vtu")
    assert np.array_equal(m.points, ref.points)
    assert [c.type for c in m.cells] == ["tetra"]
    assert np.array_equal(m.cells[0].data, ref.tets)
    assert np.array_equal(m.cell_data["region"][0], ref.region)
    assert np.array_equal(m.cell_data["min_dihedral"][0], np.arange(len(ref.tets)) / 7 + 1e-300)
    assert np.array_equal(m.point_data["boundary_marker"], ref.markers())


@pytest.mark.parametrize("suffix", ["", "-ascii"])
def test_meshio_reads_xdmf_mesh_and_facets(cubes, suffix):
    meshio = require("meshio", "python3-meshio")
    require("h5py", "python3-h5py")
    stem, ref = cubes
    m = meshio.read(stem + suffix + ".xdmf")
    assert np.array_equal(m.points, ref.points)
    assert [c.type for c in m.cells] == ["tetra"]
    assert np.array_equal(m.cells[0].data, ref.tets)
    assert np.array_equal(m.cell_data["region"][0], ref.region)
    assert field_names(m) == {n: [t, 3] for t, n in REGIONS.items()}
    f = meshio.read(stem + suffix + "_facets.xdmf")
    assert np.array_equal(f.points, ref.points)
    assert [c.type for c in f.cells] == ["triangle"]
    assert tagged_facets(f.cells[0].data, f.cell_data["facet_tags"][0]) == tagged_facets(ref.facets, ref.facet_tags)
    assert field_names(f) == {n: [t, 2] for t, n in FACETS.items()}


def test_meshio_reads_medit(cubes):
    meshio = require("meshio", "python3-meshio")
    stem, ref = cubes
    m = meshio.read(stem + ".mesh")
    assert np.array_equal(m.points, ref.points)
    tets, tags = blocks(m, "tetra", "medit:ref")
    assert np.array_equal(tets, ref.tets) and np.array_equal(tags, ref.region)
    tri, tri_tags = blocks(m, "triangle", "medit:ref")
    assert tagged_facets(tri, tri_tags) == tagged_facets(ref.facets, ref.facet_tags)
    assert np.array_equal(m.point_data["medit:ref"], ref.markers())


def test_meshio_reads_abaqus_inp_with_sets_and_faces(cubes):
    meshio = require("meshio", "python3-meshio")
    stem, ref = cubes
    m = meshio.read(stem + ".inp")
    assert np.allclose(m.points, ref.points, rtol=5e-14, atol=0)
    assert [c.type for c in m.cells] == ["tetra"]
    assert np.array_equal(m.cells[0].data, ref.tets)
    for tag, region in REGIONS.items():
        name = region.replace(" ", "_")
        assert np.array_equal(np.sort(m.cell_sets[name][0]), np.flatnonzero(ref.region == tag))
    # C3D4 face k (Abaqus: S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1),
    # reversed, is the outward facet: the surfaces are exactly the groups.
    faces = {1: (0, 2, 1), 2: (0, 1, 3), 3: (1, 2, 3), 4: (2, 0, 3)}
    for tag, group in FACETS.items():
        assert np.array_equal(np.sort(m.point_sets[group]), np.unique(ref.facets[ref.facet_tags == tag]))
        got = set()
        for side, local in faces.items():
            for e in m.cell_sets.get(f"_{group}_S{side}", [[]])[0]:
                got.add(oriented(ref.tets[e][list(local)]))
        assert got == {k for k, v in tagged_facets(ref.facets, ref.facet_tags).items() if v == tag}


# ---- gmsh ----------------------------------------------------------------------

@pytest.mark.parametrize("suffix", ["", "-22", "-data", "-ascii", "-22-ascii"])
def test_gmsh_check_accepts_msh(cubes, suffix):
    stem, ref = cubes
    r = subprocess.run(["gmsh", "-check", stem + suffix + ".msh"], capture_output=True, text=True, timeout=60)
    out = r.stdout + r.stderr
    assert r.returncode == 0 and "Error" not in out, out
    assert f"{len(ref.points)} nodes" in out, out


@pytest.mark.parametrize("suffix", ["", "-22"])
def test_gmsh_api_reads_named_physical_groups(cubes, suffix):
    gmsh = require("gmsh", "python3-gmsh")
    stem, ref = cubes
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(stem + suffix + ".msh")
        groups = {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        expect = {(3, t): n for t, n in REGIONS.items()}
        expect.update({(2, t): n for t, n in FACETS.items()})
        assert groups == expect
        tets, facets = {}, {}
        for (dim, tag) in groups:
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                types, _, nodes = gmsh.model.mesh.getElements(dim, entity)
                assert list(types) == [4 if dim == 3 else 2]
                cells = nodes[0].reshape(-1, 4 if dim == 3 else 3).astype(np.int64) - 1
                if dim == 3:
                    tets.update(tagged_tets(cells, [tag] * len(cells)))
                else:
                    facets.update(tagged_facets(cells, [tag] * len(cells)))
        assert tets == tagged_tets(ref.tets, ref.region)
        assert facets == tagged_facets(ref.facets, ref.facet_tags)
    finally:
        gmsh.finalize()


# ---- dolfinx -------------------------------------------------------------------

@pytest.mark.parametrize("suffix", ["", "-ascii"])
def test_dolfinx_reads_xdmf_mesh_cell_and_facet_tags(cubes, suffix):
    require("dolfinx", "python3-dolfinx")
    cpp = require("dolfinx.cpp", "python3-dolfinx")
    from mpi4py import MPI
    from dolfinx.io import XDMFFile
    stem, ref = cubes
    encoding = XDMFFile.Encoding.ASCII if suffix else XDMFFile.Encoding.HDF5
    with XDMFFile(MPI.COMM_WORLD, stem + suffix + ".xdmf", "r", encoding=encoding) as f:
        mesh = f.read_mesh(name="mesh")
        cell_tags = f.read_meshtags(mesh, name="mesh")
    assert mesh.geometry.dim == 3 and mesh.topology.dim == 3
    mesh.topology.create_connectivity(2, 3)
    with XDMFFile(MPI.COMM_WORLD, stem + suffix + "_facets.xdmf", "r", encoding=encoding) as f:
        facet_tags = f.read_meshtags(mesh, name="facets")
    original = np.asarray(mesh.geometry.input_global_indices)
    x = np.empty((len(original), 3))
    x[original] = mesh.geometry.x
    assert np.array_equal(x, ref.points)

    def tags(t):
        nodes = cpp.mesh.entities_to_geometry(mesh._mesh, t.dim, t.indices, False)
        return {frozenset(int(original[v]) for v in e): int(g) for e, g in zip(nodes, t.values)}

    assert tags(cell_tags) == {frozenset(t): g for t, g in zip(ref.tets.tolist(), ref.region.tolist())}
    assert tags(facet_tags) == {frozenset(f): g for f, g in zip(ref.facets.tolist(), ref.facet_tags.tolist())}


# ---- VTK -----------------------------------------------------------------------

@pytest.mark.parametrize("suffix", ["", "-z", "-ascii"])
def test_vtk_reads_vtu(cubes, suffix):
    vtk = require("vtk", "python3-vtk9")
    from vtk.util.numpy_support import vtk_to_numpy
    stem, ref = cubes
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(stem + suffix + ".vtu")
    r.Update()
    assert r.GetErrorCode() == 0
    g = r.GetOutput()
    assert np.array_equal(vtk_to_numpy(g.GetPoints().GetData()), ref.points)
    assert np.array_equal(vtk_to_numpy(g.GetCellTypesArray()), np.full(len(ref.tets), 10))
    assert np.array_equal(vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4), ref.tets)
    assert np.array_equal(vtk_to_numpy(g.GetCellData().GetArray("region")), ref.region)
    # VTK's own measure: every tetrahedron has positive volume.
    q = vtk.vtkMeshQuality()
    q.SetInputData(g)
    q.SetTetQualityMeasureToVolume()
    q.Update()
    assert (vtk_to_numpy(q.GetOutput().GetCellData().GetArray("Quality")) > 0).all()


# ---- CalculiX ------------------------------------------------------------------

CALCULIX_DECK = """*INCLUDE, INPUT=cubes.inp
*MATERIAL, NAME=SOFT
*ELASTIC
1000., 0.3
*MATERIAL, NAME=STIFF
*ELASTIC
10000., 0.3
*SOLID SECTION, ELSET=left_material, MATERIAL=SOFT
*SOLID SECTION, ELSET=domain_8, MATERIAL=STIFF
*BOUNDARY
domain_border, 1, 3, 0.
*STEP
*STATIC
*DSLOAD
boundary, P, 1.
*NODE PRINT, NSET=interface_3_8
U
*END STEP
"""


def test_calculix_solves_with_the_inp_sets_and_surfaces(cubes, tmp_path):
    """CalculiX (ccx) reads the C3D4 .inp, puts a material on each region's
    *ELSET, clamps the *NSET domain_border (the x and y sides) and pushes
    with a pressure on the *SURFACE boundary (the z = const sides, as
    element faces S1–S4).  Pressure acts into the body: interface nodes near
    the bottom move up (+z), near the top down — faces on the wrong side
    would pull instead."""
    ccx = "/usr/bin/ccx"
    if not os.path.exists(ccx):
        pytest.fail("ccx not found: install Debian's calculix-ccx (scripts/setup.sh)")
    stem, ref = cubes
    shutil.copy(stem + ".inp", tmp_path / "cubes.inp")
    (tmp_path / "job.inp").write_text(CALCULIX_DECK)
    r = subprocess.run([ccx, "-i", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    out = r.stdout + r.stderr
    assert r.returncode == 0 and "*ERROR" not in out, out
    u = {}
    for line in (tmp_path / "job.dat").read_text().splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[0].isdigit():
            u[int(parts[0]) - 1] = [float(v) for v in parts[1:]]
    interface = np.unique(ref.facets[ref.facet_tags == 3])
    assert set(u) == set(interface.tolist())
    clamped = set(np.unique(ref.facets[ref.facet_tags == 2]).tolist())
    assert all(u[v] == [0.0, 0.0, 0.0] for v in interface if v in clamped)
    free = [v for v in interface if v not in clamped]
    z = ref.points[:, 2]
    lo, hi = z.min(), z.max()
    bottom = [u[v][2] for v in free if z[v] < lo + 0.4 * (hi - lo)]
    top = [u[v][2] for v in free if z[v] > hi - 0.4 * (hi - lo)]
    assert bottom and top and min(bottom) > 0 > max(top), (bottom, top)
