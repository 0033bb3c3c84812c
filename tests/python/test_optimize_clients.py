"""An optimised, locally refined mesh (--optimize on a one-pixel atlas slice,
where refinement inserts Steiner points) read back by meshio from .vtu and
.msh: the same points and triangles as the Triangle files written in the same
run, every triangle at or above its certified_min_angle cell data, the
minimum angle >= 28 degrees, and the report's refinement figures.
"""
import json
import os

import numpy as np

from conftest import Reference, canonical_triangle, require, run_warpmesh

SLICE = "mesher/examples/brain_axial_s128_labels16.pgm"


def min_angles(points, triangles):
    p = points[triangles][:, :, :2]
    out = np.full(len(triangles), 180.0)
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        c = np.einsum("ij,ij->i", u, v) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        out = np.minimum(out, np.degrees(np.arccos(np.clip(c, -1, 1))))
    return out


def test_meshio_reads_an_optimised_refined_mesh(tmp_path, root):
    meshio = require("meshio", "python3-meshio")
    stem = str(tmp_path / "brain")
    run_warpmesh([os.path.join(root, SLICE), "--label", "nonzero", "--spacing", "1", "--optimize",
                  "-o", stem + ".node", "--also", stem + ".vtu", "--also", stem + ".msh", "--msh-cell-data",
                  "--report", stem + ".json"], tmp_path)
    with open(stem + ".json") as f:
        report = json.load(f)
    opt = report["optimize"]
    assert opt["inserted_vertices"] > 0 and opt["refined_triangles"] > 0
    assert opt["min_angle_after_deg"] >= 28
    ref = Reference(stem)
    for path in (stem + ".vtu", stem + ".msh"):
        m = meshio.read(path)
        tris = m.cells_dict["triangle"]
        assert np.array_equal(m.points[:, :2], ref.points), path
        # (.msh lists the triangles grouped by region: compare as sets)
        assert sorted(map(canonical_triangle, tris.tolist())) == sorted(map(canonical_triangle, ref.triangles.tolist())), path
        mins = min_angles(m.points, tris)
        assert mins.min() >= 28, path
        assert abs(mins.min() - opt["min_angle_after_deg"]) < 1e-6
        cert = np.asarray(m.cell_data_dict["certified_min_angle"]["triangle"])
        assert len(cert) == len(tris)
        assert np.all(mins >= cert - 1e-7), path
        assert cert.min() >= opt["certified_floor_deg"] - 1e-12
