"""examples/batch_dask.py: every slice of a label stack meshed on a dask
LocalCluster; the files do not depend on the number of workers."""
import importlib.util
import os

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")


def load_example(root):
    spec = importlib.util.spec_from_file_location("batch_dask", root / "examples" / "batch_dask.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def label_stack(n=6, size=48):
    """Two organs (labels 3 and 7) growing and moving from slice to slice; the
    first slice is empty."""
    y, x = np.mgrid[0:size, 0:size]
    stack = np.zeros((n, size, size), np.uint16)
    for k in range(1, n):
        stack[k][(x - 16) ** 2 + (y - 20) ** 2 <= (3 + 2 * k) ** 2] = 3
        stack[k][(abs(x - 30 - k) <= 4 + k) & (abs(y - 32) <= 5)] = 7
    return stack


def run(mod, workers, slices, out):
    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        return mod.mesh_volume(client, slices, str(out), labels="nonzero", spacing=1.0, graded=True)


def test_every_slice_meshed_and_files_identical_for_1_and_2_workers(root, tmp_path):
    mod = load_example(root)
    stack = label_stack()
    rows1 = run(mod, 1, list(stack), tmp_path / "w1")
    rows2 = run(mod, 2, list(stack), tmp_path / "w2")

    assert [r["slice"] for r in rows2] == list(range(len(stack)))
    assert rows2[0]["triangles"] == 0 and rows2[0]["file"] == ""  # the empty slice, with the reason
    assert "no nonzero pixels" in rows2[0]["note"]
    for r in rows2[1:]:
        assert r["triangles"] > 0 and float(r["certified_min_deg"]) > 0 and r["seconds"] > 0
    assert [r["triangles"] for r in rows2[1:]] == sorted(r["triangles"] for r in rows2[1:])  # growing organs

    names = sorted(os.listdir(tmp_path / "w1"))
    assert names == sorted(os.listdir(tmp_path / "w2"))
    assert names == sorted(["summary.csv", "timings.csv"] + [f"slice_{k:04d}.vtu" for k in range(1, len(stack))])
    for name in names:
        if name != "timings.csv":  # measured times differ from run to run
            assert (tmp_path / "w1" / name).read_bytes() == (tmp_path / "w2" / name).read_bytes(), name
    # And the same as meshing the slice directly.
    import warpmesh

    direct = warpmesh.mesh(stack[3], labels="nonzero", graded=True)
    assert rows1[3]["triangles"] == len(direct.triangles)


def test_slices_given_as_image_files(root, tmp_path):
    mod = load_example(root)
    files = [str(root / "tests/data/abdomen_axial_z024_labels16.pgm"),
             str(root / "mesher/examples/abdomen_axial_z040_labels16.pgm")]
    rows = run(mod, 2, files, tmp_path)
    assert [r["triangles"] > 1000 for r in rows] == [True, True]
