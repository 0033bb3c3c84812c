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


def test_relative_output_directory_with_workers_running_elsewhere(root, tmp_path, monkeypatch):
    # Issue 27: `batch_dask.py -o out/` failed when the workers ran in another
    # directory (the client made out/ in its own directory, the workers wrote
    # into theirs).  Now the client writes every file: a real process-based
    # LocalCluster whose workers moved to another directory leaves nothing
    # there, and out/ (relative to the client) gets the same files as a
    # thread cluster in the client's directory.
    mod = load_example(root)
    stack = label_stack(4)
    client_dir, worker_dir = tmp_path / "client", tmp_path / "workers"
    client_dir.mkdir()
    worker_dir.mkdir()
    monkeypatch.chdir(client_dir)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        client.run(os.chdir, str(worker_dir))
        assert set(client.run(os.getcwd).values()) == {str(worker_dir)}
        rows = mod.mesh_volume(client, list(stack), "out", labels="nonzero", spacing=1.0, graded=True)
        # A slice that fails for a reason other than InputError (here an
        # option mesh() does not take) is a row with the error, not a crash.
        bad = mod.mesh_volume(client, [stack[2]], "bad", labels="nonzero", colour="red")
    assert os.listdir(worker_dir) == []
    assert [r["triangles"] > 0 for r in rows] == [False, True, True, True]
    names = sorted(os.listdir(client_dir / "out"))
    assert names == sorted(["summary.csv", "timings.csv"] + [f"slice_{k:04d}.vtu" for k in (1, 2, 3)])
    ref = run(mod, 1, list(stack), tmp_path / "threads")
    assert [r["triangles"] for r in ref] == [r["triangles"] for r in rows]
    for name in names:
        if name != "timings.csv":
            assert (client_dir / "out" / name).read_bytes() == (tmp_path / "threads" / name).read_bytes(), name
    assert bad[0]["file"] == "" and bad[0]["note"].startswith("error: TypeError"), bad[0]["note"]
