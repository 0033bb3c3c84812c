"""A real 3D solve on warpmesh tetrahedra (issue 30, item 4): -Δu = f in the
unit ball with the manufactured smooth solution u = (1 - r²) cos(x) e^(y/2),
u = 0 on the mesh's boundary, P1 Lagrange in FEniCSx (Debian's dolfinx 0.5).
The meshes come from `warpmesh mesh3d --shape sphere:0,0,0,1 --spacing h -o
ball.xdmf` at four spacings and are read as a user reads them: the mesh from
ball.xdmf, the Dirichlet facets tagged "boundary" (1) from ball_facets.xdmf.

Expected rate: the mesh covers the polyhedron Ω_h whose boundary vertices lie
on the sphere; u vanishes on the sphere, so on ∂Ω_h it is O(h²) (the faces'
distance to the sphere), which costs O(h²) in L², the order of P1's
interpolation error: L² rate 2 (asserted ≥ 1.9).
"""
import subprocess

import numpy as np
import pytest

from conftest import ball_error, executable, read_xdmf, require

SPACINGS = [0.2, 0.15, 0.1, 0.075]


def solve_ball(stem):
    """L² error of the P1 solution on STEM.xdmf with u = 0 on facet tag 1."""
    require("dolfinx", "python3-dolfinx")
    mesh, _, facets = read_xdmf(stem)
    return ball_error(mesh, facets.indices[facets.values == 1])


@pytest.fixture(scope="module")
def errors(tmp_path_factory):
    d = tmp_path_factory.mktemp("ball")
    out = []
    for h in SPACINGS:
        stem = str(d / f"ball-{h}")
        subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--shape", "sphere:0,0,0,1", "--spacing", str(h),
                        "-o", stem + ".xdmf", "--quiet"], check=True, timeout=120)
        out.append(solve_ball(stem))
    return np.array(out)


def test_p1_converges_at_second_order_in_l2(errors):
    rate = np.polyfit(np.log(SPACINGS), np.log(errors), 1)[0]
    assert rate >= 1.9, (rate, errors)
    assert np.all(np.diff(errors) < 0), errors
