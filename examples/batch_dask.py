#!/usr/bin/env python3
"""Mesh every slice of a label volume on a dask.distributed cluster.

    # a local cluster of 2 workers, the slices of a stack of PGM/PNG files:
    examples/batch_dask.py --workers 2 --labels nonzero --spacing 2 -o out/ slice_*.pgm
    # a real cluster (workers started with `dask worker tcp://host:8786`):
    examples/batch_dask.py --scheduler tcp://host:8786 --labels nonzero -o out/ volume.npy

Inputs: image files (one slice each, in the order given) or one .npy array of
shape (slices, rows, columns).  Outputs in the output directory: one mesh per
slice, slice_NNNN.vtu (warpmesh's writer), and summary.csv: per slice its
triangles, vertices and certified angle bounds.  Both are deterministic: they
depend on the slices and the options only, not on the number of workers or
which worker meshed which slice.  The time each slice took (a measurement, so
never the same twice) goes to timings.csv and the printed table.

Each task meshes one slice with one OpenMP thread: the parallelism is across
slices, and warpmesh releases the GIL while meshing, so thread workers
(processes=False) mesh in parallel too.

Where the files go: the workers mesh and send each mesh's bytes back; the
client writes every file into the output directory, relative to its own
working directory.  So workers need no shared file system, and may run in
any directory or on other machines.  Image files given as inputs are read by
the workers, by absolute path (a shared file system for those, or a .npy
volume, which the client sends).  A slice warpmesh refuses (an empty slice)
gets a row with the reason and no file; a slice that fails otherwise gets a
row with the error, the batch goes on, and the script exits with status 1.
"""
import argparse
import csv
import os
import sys
import time

import numpy as np

import warpmesh

SUMMARY_FIELDS = ["slice", "file", "triangles", "vertices", "certified_min_deg", "certified_max_deg", "note"]


def mesh_slice(index, pixels, options):
    """Mesh one slice (a 2D array, or a path to an image) on a worker; return
    its summary row, the bytes of its slice_NNNN.vtu (None without a mesh)
    and the seconds it took.  A slice warpmesh refuses (no region in it, e.g.
    an empty slice of an organ's labels) gets a row with 0 triangles, no file
    and the reason in "note"; any other failure of the slice (an unreadable
    file, out of memory) a row with "error: ..." in "note"."""
    import tempfile

    t0 = time.perf_counter()
    name = f"slice_{index:04d}.vtu"
    row = {"slice": index, "file": "", "triangles": 0, "vertices": 0,
           "certified_min_deg": "", "certified_max_deg": "", "note": ""}
    data = None
    try:
        image = warpmesh.read_image(pixels) if isinstance(pixels, (str, os.PathLike)) else pixels
        m = warpmesh.mesh(image, threads=1, **options)
        # Written on the worker into a private temporary directory, sent back
        # as bytes.
        with tempfile.TemporaryDirectory(prefix="warpmesh-slice-") as tmp:
            path = os.path.join(tmp, name)
            m.write(path)
            with open(path, "rb") as f:
                data = f.read()
    except warpmesh.InputError as e:
        row["note"] = str(e)
    except Exception as e:  # noqa: BLE001 - reported per slice, the batch goes on
        row["note"] = f"error: {type(e).__name__}: {e}"
    else:
        lo, hi = m.certified or ("", "")
        row.update(file=name, triangles=len(m.triangles), vertices=len(m.points),
                   certified_min_deg=repr(lo), certified_max_deg=repr(hi))
    return row, data, time.perf_counter() - t0


def write_atomically(path, data, mode="wb"):
    """Write `data` to `path` through a temporary file in the same directory."""
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, mode, **({} if "b" in mode else {"newline": ""})) as f:
        f.write(data)
    os.replace(tmp, path)


def mesh_volume(client, slices, out_dir, **options):
    """Mesh each slice on the cluster of `client` (dask.distributed.Client);
    write the meshes, summary.csv and timings.csv into out_dir (relative to
    this process's working directory: the client writes every file).
    `slices` is a sequence of 2D arrays or image paths (relative paths are
    made absolute here); `options` are warpmesh.mesh()'s.  Returns the rows
    in slice order, each with its "seconds"."""
    import io

    os.makedirs(out_dir, exist_ok=True)
    slices = [os.path.abspath(s) if isinstance(s, (str, os.PathLike)) else s for s in slices]
    futures = [client.submit(mesh_slice, k, s, options, pure=False) for k, s in enumerate(slices)]
    rows = []
    summary, timings = io.StringIO(), io.StringIO()
    w_summary = csv.DictWriter(summary, fieldnames=SUMMARY_FIELDS, lineterminator="\n")
    w_summary.writeheader()
    w_timings = csv.writer(timings, lineterminator="\n")
    w_timings.writerow(["slice", "seconds"])
    for future in futures:  # in submission order: slice order
        row, data, seconds = future.result()
        future.release()  # the mesh's bytes are not kept on the cluster
        if data is not None:
            write_atomically(os.path.join(out_dir, row["file"]), data)
        w_summary.writerow(row)
        w_timings.writerow([row["slice"], f"{seconds:.6f}"])
        rows.append(dict(row, seconds=seconds))
    write_atomically(os.path.join(out_dir, "summary.csv"), summary.getvalue(), "w")
    write_atomically(os.path.join(out_dir, "timings.csv"), timings.getvalue(), "w")
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("inputs", nargs="+", help="image files (one slice each) or one .npy volume")
    p.add_argument("-o", "--out", required=True, help="output directory")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running dask scheduler, e.g. tcp://host:8786")
    where.add_argument("--workers", type=int, default=2, help="local cluster of this many workers (default 2)")
    p.add_argument("--labels", help='label mode: "nonzero", "3", "51,52"')
    p.add_argument("--iso", type=float, help="threshold mode: the iso value")
    p.add_argument("--spacing", type=float, default=1.0)
    p.add_argument("--graded", action="store_true")
    a = p.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    if len(a.inputs) == 1 and a.inputs[0].endswith(".npy"):
        slices = list(np.load(a.inputs[0]))
    else:
        slices = [os.path.abspath(x) for x in a.inputs]
    options = dict(labels=a.labels, iso=a.iso, spacing=a.spacing, graded=a.graded)
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        client = Client(LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=False,
                                     dashboard_address=None))
    with client:
        t0 = time.perf_counter()
        rows = mesh_volume(client, slices, a.out, **options)
        wall = time.perf_counter() - t0
    print(f"{'slice':>5}  {'triangles':>10}  {'certified angles (deg)':>26}  {'seconds':>8}")
    for r in rows:
        bounds = f"[{float(r['certified_min_deg']):.4g}, {float(r['certified_max_deg']):.4g}]" if r["file"] else "(none)"
        print(f"{r['slice']:>5}  {r['triangles']:>10}  {bounds:>26}  {r['seconds']:>8.3f}")
    print(f"{len(rows)} slices in {wall:.2f} s; meshes, summary.csv and timings.csv in {a.out}")
    failed = [r for r in rows if r["note"].startswith("error: ")]
    for r in failed:
        print(f"slice {r['slice']}: {r['note']}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
