"""Mesh a label volume larger than any worker's memory on a dask.distributed
cluster into a partitioned mesh (.pvtu) that no process ever holds whole.

Every block of lattice cubes is meshed on a worker from its part of the
volume only (a chunked zarr array or a .npy memmap; mesh3d_block_read reads
the block, its halo and its voxels' neighbourhoods), written there as a .vtu
piece (write_block: GlobalIds from the lattice keys, equal in every piece
that shares a vertex), and only the piece's metadata comes back.  The driver
writes the .pvtu (write_pvtu), refusing pieces that do not tile the lattice
exactly once; ParaView and VTK read it as one mesh.  Several materials,
listed (materials="all" depends on the whole volume's labels), or one
region (--label): then the workers first find the whole region's facts
from parts of the volume that tile it (region_part_facts_read: its voxel
box, where the lattice lies, its voxels, the distance field's minimum and
depth), which the driver merges (merge_region_facts) and every block gets.

    python3 examples/dask_partitioned3d.py VOLUME -o OUT.pvtu (--materials L,L,... | --label L)
            [--spacing S] [--voxel-size X[,Y,Z]] [--block N] [--workers W] [--memory-limit 500MB]
    python3 examples/dask_partitioned3d.py --upsample SOURCE FACTOR VOLUME

VOLUME is a .zarr directory or a .npy file of integer labels indexed
(z, y, x); a zarr's "voxel_size" attribute (x, y, z) is its default voxel
size.  --upsample writes SOURCE (a NRRD, NIfTI or TIFF label volume) grown
FACTOR times by nearest neighbour, slab by slab, as VOLUME (.zarr, .npy, or
a raw .nrrd for `warpmesh mesh3d`), with its voxel size (the source's index
axes; its origin and direction are dropped).
"""
import argparse
import os
import resource
import sys
import time

import numpy as np

import warpmesh


def open_volume(path):
    """The label volume at `path`, nothing read yet: a zarr array or a .npy
    memmap, indexed (z, y, x)."""
    if not os.path.exists(path):
        raise warpmesh.InputError(f"no volume at {path!r}")
    if str(path).endswith(".npy"):
        volume = np.load(path, mmap_mode="r")
    else:
        import zarr
        try:
            volume = zarr.open_array(str(path), mode="r")
        except Exception:
            raise warpmesh.InputError(f"{path!r} is neither a .npy file nor a zarr array") from None
    if volume.ndim != 3 or not np.issubdtype(volume.dtype, np.integer):
        raise warpmesh.InputError(f"{path!r} is a {volume.dtype} array of shape {volume.shape}: give 3D integer labels")
    return volume


def peak_memory_mb():
    """This process's peak resident memory (VmHWM), in MB."""
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmHWM")) / 1024


def cpu_seconds():
    """This process's CPU time so far (user and system), in seconds."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def mesh_piece(path, lo, hi, out, options):
    """On a worker: mesh the cubes [lo, hi) from their part of the volume
    and write the piece to `out`.  Returns its metadata with "voxels_read"
    (the largest part read) and "seconds" (the CPU time it took), the
    worker's process id, its peak memory (MB) and CPU time (s) so far."""
    start, volume, read_sizes = cpu_seconds(), open_volume(path), [0]

    def read(start, stop):
        read_sizes.append(int(np.prod(np.subtract(stop, start))))
        return np.asarray(volume[start[0]:stop[0], start[1]:stop[1], start[2]:stop[2]])

    block = warpmesh.mesh3d_block_read(read, volume.shape, lo, hi, **options)
    piece = warpmesh.write_block(block, out)
    piece.update(voxels_read=max(read_sizes), seconds=cpu_seconds() - start)
    return piece, os.getpid(), (peak_memory_mb(), cpu_seconds())


def region_part(path, start, stop, options):
    """On a worker: the region's facts of the voxels [start, stop), reading
    only the part they depend on."""
    volume = open_volume(path)
    read = lambda a, b: np.asarray(volume[a[0]:b[0], a[1]:b[1], a[2]:b[2]])
    return warpmesh.region_part_facts_read(read, volume.shape, start, stop, **options)


def region_facts(client, path, chunk=64, **options):
    """One region's facts (label=) of the volume at `path`: the workers'
    facts of its chunks of `chunk` voxels a side, merged."""
    shape = open_volume(path).shape
    starts = [(z, y, x) for z in range(0, shape[0], chunk) for y in range(0, shape[1], chunk) for x in range(0, shape[2], chunk)]
    futures = [client.submit(region_part, str(path), s, tuple(min(a + chunk, n) for a, n in zip(s, shape)), options,
                             pure=False) for s in starts]
    return warpmesh.merge_region_facts(client.gather(futures))


def blocks_of(cubes, block):
    """The [lo, hi) cube ranges of `block` cubes a side that tile `cubes`."""
    return [((x, y, z), (min(x + block, cubes[0]), min(y + block, cubes[1]), min(z + block, cubes[2])))
            for z in range(0, cubes[2], block) for y in range(0, cubes[1], block) for x in range(0, cubes[0], block)]


def mesh_partitioned(client, path, out, block=32, progress=None, **options):
    """Mesh the label volume at `path` (materials= a label list, or one
    region: label=, and mesh3d's options) in blocks of `block` cubes a side on the dask
    `client`'s workers, as the .pvtu `out` and its pieces OUT_NNNNN.vtu.
    Returns the pieces (write_block's metadata) and, by worker process id,
    its peak memory (MB) and CPU time (s).  progress(done, total) after every
    block."""
    import distributed

    if block < 1:
        raise warpmesh.InputError(f"a block must be at least 1 cube a side, got {block}")
    volume = open_volume(path)
    if options.get("materials") is None:
        options = dict(options, region_facts=region_facts(client, path, **options))
    cubes = warpmesh.lattice3d(np.asarray(volume[:2, :2, :2]), region=((0, 0, 0), volume.shape), **options)
    ranges = blocks_of(cubes, block)
    stem = os.path.splitext(os.path.abspath(out))[0]
    os.makedirs(os.path.dirname(stem), exist_ok=True)
    futures = [client.submit(mesh_piece, str(path), lo, hi, f"{stem}_{i:05d}.vtu", options, pure=False)
               for i, (lo, hi) in enumerate(ranges)]
    pieces, workers = [None] * len(futures), {}
    index = {f.key: i for i, f in enumerate(futures)}
    for done, future in enumerate(distributed.as_completed(futures), 1):
        try:
            piece, pid, figures = future.result()
        except distributed.KilledWorker:
            raise MemoryError(f"a worker died meshing the cubes {ranges[index[future.key]]} (over its memory "
                              f"limit?): take smaller blocks") from None
        pieces[index[future.key]] = piece
        workers[pid] = tuple(map(max, figures, workers.get(pid, figures)))
        if progress:
            progress(done, len(futures))
    warpmesh.write_pvtu(out, pieces)
    return pieces, workers


def upsample(source, factor, path, slab=64):
    """Write the label volume `source` grown `factor` times by nearest
    neighbour to `path` (.zarr, .npy or raw .nrrd), `slab` z-planes at a time."""
    if factor < 1:
        raise warpmesh.InputError(f"the upsampling factor must be a whole number >= 1, got {factor}")
    v = warpmesh.read_volume(source)
    if not v.integer_valued:
        raise warpmesh.InputError(f"{source!r} is not a label volume (its samples are not integers)")
    labels = np.asarray(v.data).astype(np.int16 if v.data.max() < 2 ** 15 and v.data.min() >= -2 ** 15 else np.int32)
    shape = tuple(n * factor for n in labels.shape)
    size = [s / factor for s in v.spacing]
    if path.endswith(".npy"):
        out = np.lib.format.open_memmap(path, mode="w+", dtype=labels.dtype, shape=shape)
    elif path.endswith(".nrrd"):
        out = open(path, "wb")
        out.write((f"NRRD0004\ntype: {'short' if labels.dtype == np.int16 else 'int'}\ndimension: 3\n"
                   f"sizes: {shape[2]} {shape[1]} {shape[0]}\nspacings: {size[0]} {size[1]} {size[2]}\n"
                   f"endian: little\nencoding: raw\n\n").encode())
    else:
        import zarr
        out = zarr.open_array(path, mode="w", shape=shape, chunks=(slab, slab, slab), dtype=labels.dtype)
        out.attrs.update(voxel_size=size, source=os.path.basename(source), factor=factor)
    for z in range(0, shape[0], slab):
        part = labels[z // factor:-(-(z + slab) // factor)].repeat(factor, 0)[z % factor:][:slab]
        part = part.repeat(factor, 1).repeat(factor, 2)
        if path.endswith(".nrrd"):
            out.write(part.astype("<" + part.dtype.str[1:]).tobytes())
        else:
            out[z:z + len(part)] = part
    if path.endswith(".nrrd"):
        out.close()
    elif path.endswith(".npy"):
        out.flush()
    return shape, size


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("volume", nargs="?", help="a .zarr or .npy label volume (z, y, x)")
    p.add_argument("-o", "--output", help="the .pvtu to write (its pieces beside it)")
    p.add_argument("--materials", help="the labels to mesh, each its own region: 3,41,42")
    p.add_argument("--label", help="instead: the labels of one region (3,41,42 or nonzero)")
    p.add_argument("--spacing", type=float, default=None)
    p.add_argument("--voxel-size", default=None, help="x[,y,z]; default: the zarr's voxel_size attribute, else 1")
    p.add_argument("--block", type=int, default=32, help="block side in lattice cubes")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--memory-limit", default="1GB", help="each worker's memory limit (dask's: 500MB, 2GB)")
    p.add_argument("--upsample", nargs=3, metavar=("SOURCE", "FACTOR", "VOLUME"))
    a = p.parse_args()
    if a.upsample:
        source, factor, path = a.upsample
        t0 = time.perf_counter()
        if not factor.isdigit():
            p.error(f"FACTOR must be a whole number >= 1, got {factor!r}")
        shape, size = upsample(source, int(factor), path)
        print(f"{path}: {shape[2]} x {shape[1]} x {shape[0]} voxels of {size} in {time.perf_counter() - t0:.1f} s")
        return 0
    if not (a.volume and a.output and (a.materials or a.label)) or (a.materials and a.label):
        p.error("give VOLUME, -o OUT.pvtu and --materials or --label (or --upsample)")
    import distributed

    volume = open_volume(a.volume)
    size = a.voxel_size and [float(x) for x in a.voxel_size.split(",")]
    size = size or getattr(volume, "attrs", {}).get("voxel_size") or 1.0
    options = {"materials": a.materials, "label": a.label, "spacing": a.spacing, "voxel_size": size}

    def progress(done, total):  # every block on a terminal, else every tenth of them
        if sys.stderr.isatty():
            print(f"\rblocks {done} / {total}", end="" if done < total else "\n", file=sys.stderr, flush=True)
        elif done * 10 // total > (done - 1) * 10 // total:
            print(f"blocks {done} / {total}", file=sys.stderr, flush=True)

    with distributed.LocalCluster(n_workers=a.workers, threads_per_worker=1, memory_limit=a.memory_limit,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        t0 = time.perf_counter()
        pieces, workers = mesh_partitioned(client, a.volume, a.output, a.block, progress, **options)
        seconds = time.perf_counter() - t0
    tets = sum(piece["tetrahedra"] for piece in pieces)
    part = max(piece["voxels_read"] for piece in pieces) / np.prod(volume.shape)
    cpu = sum(c for _, c in workers.values())
    empty = [piece["seconds"] for piece in pieces if not piece["tetrahedra"]]
    print(f"{len(pieces)} blocks on {a.workers} workers (memory limit {a.memory_limit}) of a "
          f"{volume.nbytes / 1e9:.2f} GB volume {volume.shape[::-1]}, each reading at most {part:.2%} of it: "
          f"{tets} tetrahedra in {seconds:.1f} s, {cpu:.1f} CPU s on the workers ({tets / seconds / 1e6:.3f} M/s, "
          f"{tets / cpu / 1e6:.3f} M per CPU s); peak memory per worker "
          f"{', '.join(f'{m:.0f}' for m, _ in sorted(workers.values()))} MB, driver {peak_memory_mb():.0f} MB; "
          f"{len(empty)} blocks without tetrahedra took {sum(empty):.1f} CPU s; wrote {a.output}")
    return 0


if __name__ == "__main__":
    try:
        raise SystemExit(main())
    except (warpmesh.InputError, MemoryError) as e:
        print(f"error: {e}", file=sys.stderr)
        raise SystemExit(2)
