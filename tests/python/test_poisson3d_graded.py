"""P1 accuracy on graded 3D meshes (issue 48, item 4): the unit ball's Poisson
problem of test_poisson3d.py (smooth u = (1 - r²) cos(x) e^(y/2), u = 0 on the
mesh's boundary, FEniCSx) on `warpmesh mesh3d --shape sphere:0,0,0,1 --spacing
h --graded --max-size 4h`, read from XDMF as a user reads it.

What the issue asks, an L² rate ≥ 1.9 with the cap scaling as 4h, is not
reached at any size measured, let alone at sizes a CTest can afford, and
this test does not claim it. The rates between neighbouring spacings
(bench/accuracy/accuracy3d.py --rates, docs/3d.md "Graded meshes") climb
1.37 (h 0.1 → 0.05), 1.44, 1.57, 1.70, 1.77, 1.84 and 1.88 (0.00884 →
0.00625, 13.8 M tetrahedra). They are pre-asymptotic because the ball's
composition changes with h. The finest band and the 2h transition cells
have a thickness of a few h, so the cells of 4h cubes, which carry most of
the error (per unit volume tens of times the band's), fill a growing share
of the ball: 15 % of its volume at h = 0.1, 36 % at 0.05, 90 % at 0.00625.
The error therefore falls more slowly than h² until that share is close to
1. The cap itself is honoured (every edge ≤ 4h), and neither the quadrature
(degree 6 gives the same digits as 4) nor the boundary (the band holds under
2 % of the squared error from h = 0.05 on) is the cause.

So this test keeps the strongest check that runs fast: about 4 CPU seconds,
as test_poisson3d.py in the same run, on h = 0.1 and 0.05 (31 176 and
152 856 tetrahedra). The next halving, 0.025 (682 000 tetrahedra), alone
takes about 10 CPU seconds. A halving, so that the rate spans a factor 2 in
h: rates between nearer spacings scatter more (0.1 → 0.0707 measures 1.60,
0.0707 → 0.05 1.14).
It asserts:
  - the cap: every edge at most 4h, and cells of 4h cubes present (an edge
    above 3h) — the mesh family of the issue;
  - the mechanism: the volume share of those cells grows as h shrinks;
  - the rate between the two, ≥ 1.3 (measured 1.37): the pre-asymptotic
    rate, a regression guard. Without the cap (plain `--graded`) it is 1.20
    here and 0.22 from 0.05 to 0.025: the interior cells stop shrinking.
"""
import os
import sys

import numpy as np
import pytest

from conftest import ball_error, executable, require

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bench", "accuracy"))

SPACINGS = [0.1, 0.05]
# The pre-asymptotic rate measured between them (2026-12-07) is 1.37.
MIN_RATE = 1.3


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """[(L² error, share of the volume in cells of 4h cubes, longest edge)] per spacing."""
    require("dolfinx", "python3-dolfinx")
    import accuracy3d
    d = str(tmp_path_factory.mktemp("graded-ball"))
    out = []
    for h in SPACINGS:
        mesh, boundary = accuracy3d.warpmesh_ball(executable("WARPMESH_EXE"), h, True, d)
        out.append((ball_error(mesh, boundary), *accuracy3d.cell_sizes(mesh, h)))
    return out


def test_max_size_4h_caps_the_cells_at_4h_cubes(graded):
    for h, (_, capped, longest) in zip(SPACINGS, graded):
        assert 3 * h < longest <= 4 * h * (1 + 1e-9), (h, longest)
        assert capped > 0, h


def test_the_capped_cells_fill_a_growing_share_of_the_ball(graded):
    shares = [capped for _, capped, _ in graded]
    assert np.all(np.diff(shares) > 0), shares


def test_p1_l2_rate_with_max_size_4h(graded):
    errors = np.array([e for e, _, _ in graded])
    rate = np.log(errors[0] / errors[1]) / np.log(SPACINGS[0] / SPACINGS[1])
    assert rate >= MIN_RATE, (rate, errors)
