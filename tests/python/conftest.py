"""Shared helpers for the real-client tests (run by CTest with Debian's
/usr/bin/python3, which has meshio, gmsh, dolfinx; see tests/CMakeLists.txt).

CMake passes the executables in the environment:
  WARPMESH_EXE           the warpmesh command line
  WARPMESH_FIXTURES_EXE  tests/tools/write_fixture_meshes (a hand-built
                         two-region mesh with interfaces, written by the
                         library's writers)

The reference for every comparison is what warpmesh itself wrote in
Triangle's format in the same run (.node/.ele/.poly), read by `read_triangle`.
"""
import importlib
import os
import pathlib
import subprocess

import numpy as np
import pytest


def require(module, package):
    """Imports `module`; a missing one fails the test naming the Debian package
    (scripts/setup.sh installs it) instead of skipping silently."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        pytest.fail(f"cannot import {module} ({e}): install Debian's {package} (scripts/setup.sh)")


def executable(var):
    path = os.environ.get(var)
    if not path or not os.path.exists(path):
        pytest.fail(f"{var} is not set to an existing executable (run these tests through ctest)")
    return path


def run_mesh3d(args, cwd, expect=0):
    """Runs `warpmesh mesh3d ARGS` in `cwd`; fails the test with its stderr
    unless it exits `expect`."""
    cmd = [executable("WARPMESH_EXE"), "mesh3d", *map(str, args)]
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=300)
    assert r.returncode == expect, f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}"
    return r


def write_nrrd(path, labels, spacing=(1.0, 1.0, 1.0)):
    """A raw NRRD of uint8 labels in mm; numpy's (k, j, i) order is NRRD's i fastest."""
    k, j, i = labels.shape
    head = (f"NRRD0004\ntype: uint8\ndimension: 3\nsizes: {i} {j} {k}\nspace: left-posterior-superior\n"
            f"space directions: ({spacing[0]},0,0) (0,{spacing[1]},0) (0,0,{spacing[2]})\n"
            "space origin: (0,0,0)\nencoding: raw\n\n")
    pathlib.Path(path).write_bytes(head.encode() + np.asarray(labels).astype(np.uint8).tobytes())


def run_calculix(directory, deck):
    """Writes DIRECTORY/job.inp (`deck`), runs CalculiX (ccx) on it and
    returns the displacements its *NODE PRINT wrote to job.dat, per node set:
    {SET: {node (0-based): [ux, uy, uz]}}.  Fails the test when ccx is
    missing, exits non-zero or reports an *ERROR."""
    ccx = "/usr/bin/ccx"
    if not os.path.exists(ccx):
        pytest.fail("ccx not found: install Debian's calculix-ccx (scripts/setup.sh)")
    directory = pathlib.Path(directory)
    (directory / "job.inp").write_text(deck)
    r = subprocess.run([ccx, "-i", "job"], cwd=directory, capture_output=True, text=True, timeout=120)
    out = r.stdout + r.stderr
    assert r.returncode == 0 and "*ERROR" not in out, out
    # job.dat: per printed set a header line, then "node ux uy uz" lines.
    printed, current = {}, None
    for line in (directory / "job.dat").read_text().splitlines():
        if "displacements" in line:
            current = line.split("for set ")[1].split()[0]
            printed[current] = {}
        elif line.split() and current:
            node, *u = line.split()
            printed[current][int(node) - 1] = [float(v) for v in u]
    return printed


def p1_l2_error(mesh, boundary, exact, rhs, k=1.0):
    """The L² error against `exact` (a UFL expression) of the P1 Lagrange
    solution of -div(k grad u) = rhs with u = 0 on the facets `boundary`
    (CG with GAMG to 1e-12; the error integrated at quadrature degree 4)."""
    import ufl
    from dolfinx import fem
    from dolfinx.fem.petsc import LinearProblem
    from petsc4py import PETSc
    V = fem.FunctionSpace(mesh, ("Lagrange", 1))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    bc = fem.dirichletbc(PETSc.ScalarType(0.0), fem.locate_dofs_topological(V, mesh.topology.dim - 1, boundary), V)
    problem = LinearProblem(k * ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx, rhs * v * ufl.dx, bcs=[bc],
                            petsc_options={"ksp_type": "cg", "pc_type": "gamg", "ksp_rtol": 1e-12})
    uh = problem.solve()
    dx = ufl.dx(metadata={"quadrature_degree": 4})
    return np.sqrt(fem.assemble_scalar(fem.form((uh - exact) ** 2 * dx)))


def ball_error(mesh, boundary):
    """The L² error of the P1 solution of the unit ball's problem (issue 30,
    tests/python/test_poisson3d.py; bench/accuracy/accuracy3d.py): -Δu = f with
    the smooth u = (1 - r²) cos(x) e^(y/2), which vanishes on the sphere, and
    u = 0 on the facets `boundary` (the mesh's, whose vertices lie on it)."""
    import ufl
    assert len(boundary) > 0 and mesh.topology.dim == 3
    x = ufl.SpatialCoordinate(mesh)
    exact = (1 - ufl.dot(x, x)) * ufl.cos(x[0]) * ufl.exp(x[1] / 2)
    return p1_l2_error(mesh, boundary, exact, -ufl.div(ufl.grad(exact)))


def run_warpmesh(args, cwd):
    """Runs `warpmesh mesh ARGS --quiet` in `cwd`; fails the test with its
    stderr on a non-zero exit."""
    cmd = [executable("WARPMESH_EXE"), "mesh", *map(str, args), "--quiet"]
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}"
    return r


def write_fixtures(directory):
    """The two-region mesh with interfaces in every format: DIR/two.*"""
    r = subprocess.run([executable("WARPMESH_FIXTURES_EXE"), str(directory)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    return os.path.join(str(directory), "two")


def write_pgm(path, pixels):
    """An 8-bit binary PGM (P5) from a 2D uint8 array, row 0 at the top."""
    pixels = np.asarray(pixels, dtype=np.uint8)
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (pixels.shape[1], pixels.shape[0]))
        f.write(pixels.tobytes())


class Reference:
    """A mesh as warpmesh wrote it in Triangle's format (0-based indices).

    points (N, 2), markers (N,), triangles (T, 3), region (T,),
    segments (S, 2) with segment_tags (S,): the boundary edges (region on
    their left) followed by the interface edges, tagged as the facet tags of
    every other format.
    """

    def __init__(self, stem):
        def rows(path):
            with open(path) as f:
                lines = [ln.split("#")[0].split() for ln in f]
            return [ln for ln in lines if ln]

        node = rows(stem + ".node")
        n = int(node[0][0])
        assert node[0][1:] == ["2", "0", "1"]
        self.points = np.array([[float(r[1]), float(r[2])] for r in node[1:n + 1]])
        self.markers = np.array([int(r[3]) for r in node[1:n + 1]])
        ele = rows(stem + ".ele")
        t = int(ele[0][0])
        self.triangles = np.array([[int(v) - 1 for v in r[1:4]] for r in ele[1:t + 1]], dtype=np.int64)
        self.region = np.array([int(r[4]) for r in ele[1:t + 1]])
        poly = rows(stem + ".poly")
        s = int(poly[1][0])
        self.segments = np.array([[int(v) - 1 for v in r[1:3]] for r in poly[2:s + 2]], dtype=np.int64).reshape(-1, 2)
        self.segment_tags = np.array([int(r[3]) for r in poly[2:s + 2]], dtype=np.int64)

    def tagged_triangles(self):
        return tagged_cells(self.triangles, self.region)

    def tagged_edges(self):
        return tagged_edges(self.segments, self.segment_tags)


def canonical_triangle(t):
    """The triangle as a tuple starting at its smallest vertex, orientation kept."""
    t = [int(v) for v in t]
    k = t.index(min(t))
    return tuple(t[k:] + t[:k])


def tagged_cells(cells, tags):
    """{canonical triangle: tag}, asserting that no triangle repeats."""
    d = {canonical_triangle(c): int(g) for c, g in zip(cells, tags)}
    assert len(d) == len(cells), "a triangle appears twice"
    return d


def tagged_edges(edges, tags):
    """{frozenset edge: tag}, asserting that no edge repeats."""
    d = {frozenset(int(v) for v in e): int(g) for e, g in zip(edges, tags)}
    assert len(d) == len(edges), "an edge appears twice"
    return d


@pytest.fixture(scope="session")
def two_region(tmp_path_factory):
    """Stem of the hand-built two-region fixture files."""
    return write_fixtures(tmp_path_factory.mktemp("fixtures"))


ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    """The repository's root."""
    return ROOT


@pytest.fixture
def cli():
    """The warpmesh command line (CTest passes it in WARPMESH_EXE)."""
    return executable("WARPMESH_EXE")


def read_xdmf(path):
    """(mesh, cell tags, facet tags) from warpmesh's PATH.xdmf and
    PATH_facets.xdmf (heavy data in PATH.h5 and PATH_facets.h5, the default),
    as the docs tell users to read them."""
    require("dolfinx", "python3-dolfinx")
    from dolfinx.io import XDMFFile
    from mpi4py import MPI
    with XDMFFile(MPI.COMM_WORLD, path + ".xdmf", "r") as f:
        mesh = f.read_mesh(name="mesh")
        cells = f.read_meshtags(mesh, name="mesh")
    mesh.topology.create_connectivity(mesh.topology.dim - 1, mesh.topology.dim)
    with XDMFFile(MPI.COMM_WORLD, path + "_facets.xdmf", "r") as f:
        facets = f.read_meshtags(mesh, name="facets")
    return mesh, cells, facets
