"""A two-material 3D solve on warpmesh tetrahedra (issue 47, item 5): two
nested spheres, `warpmesh mesh3d --shapes "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"`,
k = 10 in the inner one (material 2), k = 1 in the shell (material 1),

    -div(k grad u) = 1 in the unit ball,  u = 0 on r = 1,

P1 Lagrange in FEniCSx (Debian's dolfinx 0.5), read as a user reads the
files: the mesh and its cell tags (the materials) from nested.xdmf, the facet
tags from nested_facets.xdmf, the Dirichlet facets those of the group named
"boundary" (found by name), not the interface's.

The exact solution is radial.  With the flux q(r) = k u'(r), the equation is
(r² q)' = -r², and q is bounded at 0, so q = -r/3 on both sides: the flux is
continuous at r = 1/2 by construction.  Then u' = -r/30 inside, -r/3 outside;
u(1) = 0 gives u = (1 - r²)/6 for r >= 1/2, and continuity of u at r = 1/2
gives u = 1/8 + 1/240 - r²/60 for r <= 1/2.

Expected rate: as for one region (test_poisson3d.py), the boundary and the
interface are polyhedra within O(h²) of their spheres, which costs O(h²) in
L², P1's own order: L² rate 2 (asserted >= 1.9 over three spacings).
"""
import subprocess

import numpy as np
import pytest

from conftest import executable, p1_l2_error, read_xdmf, require

SPACINGS = [0.2, 0.14, 0.1]
K = {1: 1.0, 2: 10.0}


def solve_nested(stem):
    """L² error of the P1 solution on STEM.xdmf: k by cell tag, u = 0 on the
    facets of the group "boundary"."""
    require("dolfinx", "python3-dolfinx")
    meshio = require("meshio", "python3-meshio")
    import ufl
    from dolfinx import fem

    groups = {name: int(v[0]) for name, v in meshio.read(stem + "_facets.xdmf").field_data.items()}
    assert set(groups) == {"boundary", "interface_1_2"}, groups
    mesh, cells, facets = read_xdmf(stem)
    boundary = facets.indices[facets.values == groups["boundary"]]
    interface = facets.indices[facets.values == groups["interface_1_2"]]
    assert len(boundary) > 0 and len(interface) > 0 and mesh.topology.dim == 3
    assert set(np.unique(cells.values).tolist()) == set(K)
    k = fem.Function(fem.FunctionSpace(mesh, ("DG", 0)))
    k.x.array[cells.indices] = np.vectorize(K.get)(cells.values)
    x = ufl.SpatialCoordinate(mesh)
    r2 = ufl.dot(x, x)
    exact = ufl.conditional(ufl.lt(r2, 0.25), 1 / 8 + 1 / 240 - r2 / 60, (1 - r2) / 6)
    return p1_l2_error(mesh, boundary, exact, 1.0, k)


def mesh_nested(directory, h):
    """The nested spheres at spacing h as DIRECTORY/nested-h.xdmf (+ _facets.xdmf); its stem."""
    stem = str(directory / f"nested-{h}")
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--shapes", "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5", "--spacing",
                    str(h), "-o", stem + ".xdmf", "--quiet"], check=True, timeout=120)
    return stem


@pytest.fixture(scope="module")
def errors(tmp_path_factory):
    d = tmp_path_factory.mktemp("nested")
    return np.array([solve_nested(mesh_nested(d, h)) for h in SPACINGS])


def test_p1_converges_at_second_order_in_l2_across_the_interface(errors):
    rate = np.polyfit(np.log(SPACINGS), np.log(errors), 1)[0]
    assert rate >= 1.9 and np.all(np.diff(errors) < 0), (rate, errors)


def test_the_wrong_coefficient_is_seen(tmp_path):
    """The check is sharp: the same solve with k swapped between the
    materials (k = 1 inside, 10 outside) misses the exact solution by far
    more than the discretisation error."""
    stem = mesh_nested(tmp_path, 0.2)
    right = solve_nested(stem)
    K[1], K[2] = K[2], K[1]
    try:
        wrong = solve_nested(stem)
    finally:
        K[1], K[2] = K[2], K[1]
    assert wrong > 10 * right, (wrong, right)
