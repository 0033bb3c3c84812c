"""Issue 28: a two-material Poisson problem solved with FEniCSx (Debian's
dolfinx) on warpmesh's multi-material meshes, read as a user reads them
(XDMFFile: the cell tags are the materials, facet tag 1 the outer boundary).

The two-material disc: material 2 is r < 1/2 with k = 10, material 1 is
1/2 < r < 1 with k = 1 (`--shapes "1=circle:0,0,1;2=circle:0,0,0.5"`: the
later shape wins); -div(k grad u) = 1, u = 0 on r = 1.  The flux is radial
and continuous, k u'(r) = -r/2, so

    u = (1 - r²)/4                          for 1/2 <= r <= 1,
    u = 3/16 + (1/4 - r²)/40                for r <= 1/2,

continuous with a kink on the interface.  The interface is a chain of mesh
edges with its vertices on r = 1/2, so the coefficient is wrong only in the
lenses between chords and arc (area O(h³) each, O(h²) in all) and P1 keeps its
L² rate 2 (tagging cells by centroid on a one-region mesh gives about 1).
Asserted: L² rate >= 1.9 on uniform meshes and on the same meshes with
--optimize (interface vertices slide along r = 1/2).  (Graded meshes with
--max-size 4h reach only about 1.6 at these spacings, 0.1 to 0.0125: not
asserted here.)
"""
import numpy as np
import pytest

from conftest import read_xdmf, require, run_warpmesh

SPACINGS = [0.1, 0.05, 0.025, 0.0125]
SHAPES = "1=circle:0,0,1;2=circle:0,0,0.5"
K = {1: 1.0, 2: 10.0}


def solve(stem):
    """L² error of the P1 solution on the mesh stem.xdmf."""
    require("dolfinx", "python3-dolfinx")
    import ufl
    from dolfinx import fem
    from dolfinx.fem.petsc import LinearProblem
    from petsc4py import PETSc

    mesh, cells, facets = read_xdmf(stem)
    assert set(np.unique(cells.values)) == {1, 2}
    k = fem.Function(fem.FunctionSpace(mesh, ("DG", 0)))
    k.x.array[cells.indices] = np.vectorize(K.get)(cells.values)
    V = fem.FunctionSpace(mesh, ("Lagrange", 1))
    outer = facets.indices[facets.values == 1]
    assert len(outer) > 0
    bc = fem.dirichletbc(PETSc.ScalarType(0.0), fem.locate_dofs_topological(V, 1, outer), V)
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    one = fem.Constant(mesh, PETSc.ScalarType(1.0))
    problem = LinearProblem(k * ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx, one * v * ufl.dx, bcs=[bc],
                            petsc_options={"ksp_type": "preonly", "pc_type": "lu"})
    uh = problem.solve()
    x = ufl.SpatialCoordinate(mesh)
    r2 = x[0] ** 2 + x[1] ** 2
    exact = ufl.conditional(ufl.lt(r2, 0.25), 3.0 / 16 + (0.25 - r2) / 40, (1 - r2) / 4)
    dx = ufl.dx(metadata={"quadrature_degree": 4})
    return np.sqrt(fem.assemble_scalar(fem.form((uh - exact) ** 2 * dx)))


def rate(errors):
    return np.polyfit(np.log(SPACINGS), np.log(errors), 1)[0]


@pytest.fixture(scope="module")
def errors(tmp_path_factory):
    d = tmp_path_factory.mktemp("two_materials")
    out = {}
    for h in SPACINGS:
        for name, extra in (("uniform", []), ("optimized", ["--optimize"])):
            stem = str(d / f"{name}-{h}")
            run_warpmesh(["--shapes", SHAPES, "--spacing", h, *extra, "-o", stem + ".xdmf"], d)
            out.setdefault(name, []).append(solve(stem))
    return {k: np.array(v) for k, v in out.items()}


@pytest.mark.parametrize("name", ["uniform", "optimized"])
def test_p1_converges_at_second_order_in_l2(errors, name):
    e = errors[name]
    assert rate(e) >= 1.9, (name, e, rate(e))
    assert np.all(np.diff(e) < 0), e
