"""Mesh a volume in blocks on a dask.distributed cluster and merge the
blocks into the mesh one process would make — exactly, vertex for vertex.

The BCC lattice rule is local: a block of lattice cubes meshes on its own
(warpmesh.mesh3d_block looks at the level set on the block plus a halo), and
every vertex and tetrahedron carries its global key (its lattice position),
so warpmesh.merge_blocks puts blocks meshed anywhere, in any order, back
together.  This is how a volume too large for one machine is meshed: each
worker needs its block of the volume only (--parts).

    python3 examples/dask_blocks3d.py [VOLUME.npy] [--label nonzero] [--spacing S] [--parts]
                                      [--materials all|L,L,... [--background drop|keep]]
                                      [--block N] [--workers W] [-o OUT.vtu]

Without VOLUME a demo volume (two touching balls, labels 1 and 2) is used.
With --materials every label listed (all: every label but 0) is its own
region of one conforming mesh, as warpmesh.mesh3d(volume, materials=...)
makes it; its blocks merge into that mesh exactly too, regions and
interfaces included.  With --parts (one region, or materials listed) no
worker gets the whole volume: each opens the .npy file as a memmap and
reads only its block's part (warpmesh.mesh3d_block_read); one region first
needs the whole region's facts (its voxel box, where the lattice lies;
its voxels; the distance field's minimum and depth), which the workers
find from parts of the volume that tile it (region_part_facts_read) and
the driver merges (merge_region_facts) before any block is meshed.
Without --parts the whole array is scattered to every worker once.  The result is checked against warpmesh.mesh3d of the
whole volume: the mesh and its report (but the meshing time).  Every block
carries its lattice, cube range, face rule and alphas, so merge_blocks
refuses, naming the missing cubes, a set of blocks with one lost (a failed
task) instead of returning a mesh with a hole.
"""
import argparse
import itertools
import time

import numpy as np

import warpmesh


def blocks_of(cubes, block):
    """The [lo, hi) cube ranges of `block` cubes a side that tile `cubes`."""
    ranges = [[(a, min(a + block, n)) for a in range(0, n, block)] for n in cubes]
    for (x, y, z) in itertools.product(*ranges):
        yield (x[0], y[0], z[0]), (x[1], y[1], z[1])


def _mesh_block(volume, lo, hi, options):
    return warpmesh.mesh3d_block(volume, lo, hi, **options)


def mesh_in_blocks(client, volume, block=16, **options):
    """The TetMesh of `volume` (a numpy array or a shape string; options as
    warpmesh.mesh3d's: label, iso, voxel_size, spacing, ..., or materials and
    background for several materials) meshed in blocks of `block` lattice
    cubes a side on the dask `client`'s workers."""
    cubes = warpmesh.lattice3d(volume, **options)
    data = client.scatter(volume, broadcast=True) if not isinstance(volume, str) else volume
    futures = [client.submit(_mesh_block, data, lo, hi, options, pure=False) for lo, hi in blocks_of(cubes, block)]
    return warpmesh.merge_blocks(client.gather(futures)), len(futures)


def _mesh_part(path, lo, hi, options):
    """A block that reads only its part of the .npy volume at `path` (a
    memmap: the pages of its part)."""
    volume = np.load(path, mmap_mode="r")
    read = lambda start, stop: volume[start[0]:stop[0], start[1]:stop[1], start[2]:stop[2]]
    return warpmesh.mesh3d_block_read(read, volume.shape, lo, hi, **options)


def _region_part(path, start, stop, options):
    """The region's facts of the voxels [start, stop) of the .npy volume at
    `path`, reading only the part they depend on."""
    volume = np.load(path, mmap_mode="r")
    read = lambda a, b: volume[a[0]:b[0], a[1]:b[1], a[2]:b[2]]
    return warpmesh.region_part_facts_read(read, volume.shape, start, stop, **options)


def region_facts(client, path, chunk=32, **options):
    """One region's facts (label=) of the .npy volume at `path`: the
    workers' facts of its chunks of `chunk` voxels a side, merged."""
    shape = np.load(path, mmap_mode="r").shape
    starts = itertools.product(*(range(0, n, chunk) for n in shape))
    futures = [client.submit(_region_part, str(path), s, tuple(min(a + chunk, n) for a, n in zip(s, shape)), options,
                             pure=False) for s in starts]
    return warpmesh.merge_region_facts(client.gather(futures))


def mesh_parts_in_blocks(client, path, block=16, **options):
    """The TetMesh of the label volume in the .npy file `path` (materials= a
    label list, or one region: label=), meshed in blocks of `block` cubes a
    side whose workers each read only their block's part of the file
    (warpmesh.block_voxels: the block, its window's halo and what the
    voxels' values depend on): no worker holds the whole volume, nor is it
    sent anywhere.  One region: the whole region's facts first
    (region_facts)."""
    volume = np.load(path, mmap_mode="r")
    if options.get("materials") is None:
        options = dict(options, region_facts=region_facts(client, path, **options))
    cubes = warpmesh.lattice3d(volume[:2, :2, :2], region=((0, 0, 0), volume.shape), **options)
    futures = [client.submit(_mesh_part, str(path), lo, hi, options, pure=False) for lo, hi in blocks_of(cubes, block)]
    return warpmesh.merge_blocks(client.gather(futures)), len(futures)


def same_mesh(a, b, materials):
    """Whether two TetMeshes are equal array for array (with several
    materials, the interfaces and region names too)."""
    keys = ["points", "tetrahedra", "regions", "boundary_faces", "boundary_tags"]
    if materials:
        keys += ["interfaces", "interface_regions"]
    return (all(np.array_equal(getattr(a, k), getattr(b, k)) for k in keys)
            and (not materials or a.region_names == b.region_names))


def same_report(a, b):
    """Whether two TetMeshes' reports agree but for the meshing time."""
    return {k: v for k, v in a.report.items() if k != "seconds"} == {k: v for k, v in b.report.items() if k != "seconds"}


def demo_volume(n=40):
    z, y, x = np.indices((n, n, n))
    v = np.zeros((n, n, n), np.uint8)
    v[(x - 15) ** 2 + (y - 20) ** 2 + (z - 20) ** 2 < 100] = 1
    v[(x - 26) ** 2 + (y - 20) ** 2 + (z - 21) ** 2 < 64] = 2
    return v


def main():
    import distributed

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("volume", nargs="?", help="a .npy volume indexed (z, y, x); default: a demo volume")
    p.add_argument("--label", default=None, help="the region's labels (default: nonzero)")
    p.add_argument("--materials", default=None, help="several materials instead of one region: all, or labels 3,41,42")
    p.add_argument("--background", default="drop", choices=("drop", "keep"), help="with --materials: output the background too")
    p.add_argument("--spacing", type=float, default=None)
    p.add_argument("--block", type=int, default=16, help="block side in lattice cubes")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--parts", action="store_true",
                   help="every worker reads only its block's part of the volume (a .npy memmap; --materials: a list)")
    p.add_argument("-o", "--output", default=None)
    a = p.parse_args()
    if a.parts and a.materials == "all":
        p.error("--parts needs --materials with a label list (all depends on the whole volume)")
    volume = np.load(a.volume, mmap_mode="r" if a.parts else None) if a.volume else demo_volume()
    if a.materials is not None:
        if a.label is not None:
            p.error("--label (one region) and --materials exclude each other")
        options = {"materials": a.materials, "background": a.background, "spacing": a.spacing}
    else:
        options = {"label": a.label or "nonzero", "spacing": a.spacing}
    with distributed.LocalCluster(n_workers=a.workers, threads_per_worker=1, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        t0 = time.perf_counter()
        if a.parts:
            path = a.volume
            if path is None:
                import tempfile
                path = tempfile.mkdtemp() + "/demo.npy"
                np.save(path, volume)
            merged, count = mesh_parts_in_blocks(client, path, a.block, **options)
        else:
            merged, count = mesh_in_blocks(client, volume, a.block, **options)
        t1 = time.perf_counter()
    whole = warpmesh.mesh3d(np.asarray(volume), **options)
    same = same_mesh(merged, whole, a.materials is not None) and same_report(merged, whole)
    regions = f" in {len(merged.region_names)} materials" if a.materials is not None else ""
    print(f"{count} blocks on {a.workers} workers: {len(merged.tetrahedra)} tetrahedra{regions} in {t1 - t0:.2f} s; "
          f"identical to the single-process mesh: {same}")
    if a.output:
        merged.write(a.output)
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
