"""examples/dask_blocks3d.py (issue 30, item 6): a label volume meshed in
blocks on a dask LocalCluster merges into exactly the single-process mesh —
points, tetrahedra, boundary faces and tags, bit for bit — for two block
sizes and either worker count, and for a shape in any block order; a block
given twice and a block outside the lattice are refused.  Issue 49: the
blocks of a random partition of a label volume (one region, several
materials) merge into mesh3d's mesh and report; drop, repeat or shift any
block and the merge is refused, naming what is wrong; so do blocks that
read only their part of the volume (several materials, and one region with
the whole region's facts from a reduction over the parts)."""
import importlib.util

import numpy as np
import pytest

import warpmesh
from conftest import require


def load_example(root):
    spec = importlib.util.spec_from_file_location("dask_blocks3d", root / "examples" / "dask_blocks3d.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def same(a, b):
    return (np.array_equal(a.points, b.points) and np.array_equal(a.tetrahedra, b.tetrahedra)
            and np.array_equal(a.boundary_faces, b.boundary_faces) and np.array_equal(a.boundary_tags, b.boundary_tags)
            and np.array_equal(a.regions, b.regions))


@pytest.mark.parametrize("workers, block", [(1, 7), (2, 11)])
def test_blocks_on_a_local_cluster_equal_the_whole_mesh(root, workers, block):
    distributed = require("distributed", "python3-distributed")
    mod = load_example(root)
    volume = mod.demo_volume(32)
    options = {"label": "nonzero", "voxel_size": (1.0, 1.0, 1.25), "spacing": 1.1}
    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        merged, count = mod.mesh_in_blocks(client, volume, block, **options)
    whole = warpmesh.mesh3d(volume, **options)
    cubes = warpmesh.lattice3d(volume, **options)
    assert count == np.prod([-(-n // block) for n in cubes]) > 1
    assert len(whole.tetrahedra) > 1000
    assert same(merged, whole)
    assert mod.same_report(merged, whole)


@pytest.mark.parametrize("options", [{"materials": "1,2", "spacing": 1.1}, {"label": "nonzero", "spacing": 1.1}])
def test_blocks_reading_their_parts_on_a_local_cluster(root, tmp_path, options):
    """examples/dask_blocks3d.py --parts: every worker reads only its block's
    part of a .npy memmap (one region: after the workers' reduction to the
    whole region's facts); the merge is the whole volume's mesh and report."""
    distributed = require("distributed", "python3-distributed")
    mod = load_example(root)
    volume = mod.demo_volume(32)
    np.save(tmp_path / "v.npy", volume)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        merged, count = mod.mesh_parts_in_blocks(client, tmp_path / "v.npy", 10, **options)
    whole = warpmesh.mesh3d(volume, **options)
    assert count > 8 and len(whole.tetrahedra) > 1000
    assert same(merged, whole) and mod.same_report(merged, whole)


def test_blocks_of_a_shape_in_any_order_and_a_gap_refused():
    cubes = warpmesh.lattice3d("torus:0,0,0,1,0.35", spacing=0.1)
    blocks = [warpmesh.mesh3d_block("torus:0,0,0,1,0.35", lo, hi, spacing=0.1)
              for lo, hi in [((0, 0, 0), (13, cubes[1], cubes[2])), ((13, 0, 0), cubes)]]
    assert same(warpmesh.merge_blocks(blocks[::-1]), warpmesh.mesh3d("torus:0,0,0,1,0.35", spacing=0.1))
    # The same block twice: a tetrahedron twice.
    with pytest.raises(warpmesh.InputError, match="do not merge"):
        warpmesh.merge_blocks([blocks[0], blocks[0]])
    with pytest.raises(warpmesh.InputError, match="lattice"):
        warpmesh.mesh3d_block("torus:0,0,0,1,0.35", (0, 0, 0), (cubes[0] + 1, 1, 1), spacing=0.1)


def kmeans_labels(n=22, k=4, seed=49):
    """A label volume of k nearest-centre cells (labels 1..k) inside a ball,
    0 outside: several materials meeting at junctions."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(3, n - 3, size=(k, 3))
    z, y, x = np.indices((n, n, n)).astype(float)
    d = np.stack([(x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2 for c in centres])
    v = (np.argmin(d, axis=0) + 1).astype(np.uint8)
    v[(x - n / 2) ** 2 + (y - n / 2) ** 2 + (z - n / 2) ** 2 > (0.42 * n) ** 2] = 0
    return v


def random_partition(cubes, rng):
    """The [lo, hi) ranges of a random grid partition of the cubes (0 to 2
    cuts along every axis), at least two blocks."""
    while True:
        cuts = [sorted({0, n, *rng.integers(1, n, size=rng.integers(0, 3))}) for n in cubes]
        ranges = [((x0, y0, z0), (x1, y1, z1)) for z0, z1 in zip(cuts[2], cuts[2][1:]) for y0, y1 in zip(cuts[1], cuts[1][1:])
                  for x0, x1 in zip(cuts[0], cuts[0][1:])]
        if len(ranges) >= 2:
            return [(tuple(int(v) for v in lo), tuple(int(v) for v in hi)) for lo, hi in ranges]


def report_without_time(m):
    r = dict(m.report)
    r.pop("seconds")
    return r


@pytest.mark.parametrize("options", [{"label": [1, 3], "spacing": 1.3, "voxel_size": (1.0, 1.0, 1.2)},
                                     {"materials": "all", "spacing": 1.0}])
def test_merge_refuses_a_lost_repeated_or_shifted_block(options):
    volume = kmeans_labels()
    rng = np.random.default_rng(7)
    whole = warpmesh.mesh3d(volume, **options)
    cubes = warpmesh.lattice3d(volume, **options)
    for trial in range(2):
        ranges = random_partition(cubes, rng)
        blocks = [warpmesh.mesh3d_block(volume, lo, hi, **options) for lo, hi in ranges]
        order = rng.permutation(len(blocks))
        merged = warpmesh.merge_blocks([blocks[i] for i in order])
        assert same(merged, whole)
        assert report_without_time(merged) == report_without_time(whole)
        assert merged.certified == whole.certified and merged.report["quality"]["volume"] > 0 if "quality" in whole.report \
            else merged.certified == whole.certified
        k = int(rng.integers(len(blocks)))
        lo, hi = ranges[k]
        with pytest.raises(warpmesh.InputError, match=r"are in no block.*a block is missing"):
            warpmesh.merge_blocks(blocks[:k] + blocks[k + 1:])
        with pytest.raises(warpmesh.InputError, match=r"given twice"):
            warpmesh.merge_blocks(blocks + [blocks[k]])
        # Shifted by a cube along an axis where the block is not the lattice's whole width.
        a = next(a for a in range(3) if hi[a] - lo[a] < cubes[a])
        step = 1 if hi[a] < cubes[a] else -1
        moved = [list(lo), list(hi)]
        moved[0][a] += step
        moved[1][a] += step
        shifted = blocks[:k] + [warpmesh.mesh3d_block(volume, moved[0], moved[1], **options)] + blocks[k + 1:]
        with pytest.raises(warpmesh.InputError, match=r"overlap in the cubes"):
            warpmesh.merge_blocks(shifted)
    with pytest.raises(warpmesh.InputError, match="no blocks to merge"):
        warpmesh.merge_blocks([])


def test_merge_refuses_blocks_of_different_meshes():
    volume = kmeans_labels()
    cubes = warpmesh.lattice3d(volume, label=1, spacing=1.5)
    half = cubes[0] // 2
    left, right = ((0, 0, 0), (half, cubes[1], cubes[2])), ((half, 0, 0), cubes)
    a = warpmesh.mesh3d_block(volume, *left, label=1, spacing=1.5)
    # Another distance band: the same lattice, another level set.
    with pytest.raises(warpmesh.InputError, match="different inputs"):
        warpmesh.merge_blocks([a, warpmesh.mesh3d_block(volume, *right, label=1, spacing=1.5, band=6)])
    with pytest.raises(warpmesh.InputError, match="face rules parity and delaunay"):
        warpmesh.merge_blocks([a, warpmesh.mesh3d_block(volume, *right, label=1, spacing=1.5, face_rule="parity")])
    with pytest.raises(warpmesh.InputError, match="lattices spacing 1.4"):
        warpmesh.merge_blocks([a, warpmesh.mesh3d_block(volume, *right, label=1, spacing=1.4)])
    broken = dict(a)
    del broken["facts"]
    with pytest.raises(warpmesh.InputError, match="a block without 'facts'"):
        warpmesh.merge_blocks([broken])
    with pytest.raises(warpmesh.InputError, match="not a block"):
        warpmesh.merge_blocks([a, "b"])


def region_facts(read, shape, rng, **options):
    """The whole region's facts (one region, label=) by the reduction over a
    random tiling of the volume's voxels, each part read as
    region_part_voxels names, merged in a random order."""
    tiling = random_partition(shape[::-1], rng)
    facts = [warpmesh.region_part_facts_read(read, shape, lo[::-1], hi[::-1], **options) for lo, hi in tiling]
    return warpmesh.merge_region_facts([facts[i] for i in rng.permutation(len(facts))])


@pytest.mark.parametrize("options, store", [({"materials": "1,2,3,4", "spacing": 1.0}, "npy"),
                                            ({"materials": "2,4", "background": "keep", "spacing": 1.3,
                                              "voxel_size": (1.0, 0.9, 1.2), "origin": (5.0, -3.0, 2.0)}, "npy"),
                                            ({"label": [1, 3], "spacing": 1.3, "voxel_size": (1.0, 1.0, 1.2)}, "npy"),
                                            ({"label": 2, "spacing": 0.9, "voxel_size": (0.8, 1.0, 1.1),
                                              "origin": (5.0, -3.0, 2.0)}, "zarr")])
def test_blocks_that_read_only_their_part_merge_into_the_whole_mesh(tmp_path, options, store):
    """Issue 49, item 1: each block reads only the voxels block_voxels names
    (a region of a .npy memmap or a zarr array) and is meshed from that part;
    the blocks merge into exactly the whole volume's mesh and report.  One
    region (label=): the whole region's facts first, by a reduction over a
    random tiling of the volume (each part read as region_part_voxels
    names)."""
    labels = kmeans_labels(30)
    if store == "npy":
        np.save(tmp_path / "labels.npy", labels)
        volume = np.load(tmp_path / "labels.npy", mmap_mode="r")
    else:
        zarr = require("zarr", "python3-zarr")
        volume = zarr.open_array(str(tmp_path / "labels.zarr"), mode="w", shape=labels.shape, chunks=(8, 8, 8),
                                 dtype=labels.dtype)
        volume[:] = labels
    whole = warpmesh.mesh3d(labels, **options)
    read = []

    def region(start, stop):
        read.append(int(np.prod(np.subtract(stop, start))))
        return volume[start[0]:stop[0], start[1]:stop[1], start[2]:stop[2]]

    if "label" in options:
        options = dict(options, region_facts=region_facts(region, labels.shape, np.random.default_rng(3), **options))
    cubes = warpmesh.lattice3d(labels[:2, :2, :2], region=((0, 0, 0), labels.shape), **options)
    assert cubes == warpmesh.lattice3d(labels, **{k: v for k, v in options.items() if k != "region_facts"})
    read.clear()
    halves = [[(0, n // 2), (n // 2, n)] for n in cubes]
    ranges = [((x[0], y[0], z[0]), (x[1], y[1], z[1])) for x in halves[0] for y in halves[1] for z in halves[2]]
    blocks = [warpmesh.mesh3d_block_read(region, labels.shape, lo, hi, **options) for lo, hi in ranges]
    assert max(read) < (0.6 if "materials" in options else 0.95) * labels.size  # one region: band + 2 voxels more
    merged = warpmesh.merge_blocks(blocks)
    assert same(merged, whole) and merged.region_names == whole.region_names
    assert np.array_equal(merged.interfaces, whole.interfaces)
    assert report_without_time(merged) == report_without_time(whole)
    # A part too small for its block is refused, naming what it needs.
    lo, hi = (0, 0, 0), (cubes[0] // 2, cubes[1], cubes[2])
    start, stop = warpmesh.block_voxels(labels.shape, lo, hi, **options)
    small = labels[start[0]:stop[0], start[1]:stop[1], start[2]:stop[2] - 4]
    with pytest.raises(warpmesh.InputError, match="too small"):
        warpmesh.mesh3d_block(small, lo, hi, region=(start, labels.shape), **options)


def test_a_part_of_one_region_needs_the_whole_regions_facts():
    """One region's part without the reduction's facts, with a part's facts
    only, with facts of another band, with a lost or repeated part, or cut
    too small for the facts it gives: refused, naming what is wrong."""
    volume = kmeans_labels()
    shape, options = volume.shape, {"label": 1, "spacing": 1.0}
    read = lambda start, stop: volume[start[0]:stop[0], start[1]:stop[1], start[2]:stop[2]]
    part = dict(region=((0, 0, 0), shape), **options)
    with pytest.raises(warpmesh.InputError, match="needs the whole region's facts"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), **part)
    with pytest.raises(warpmesh.InputError, match="label mode"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region=((0, 0, 0), shape), iso=0.5, spacing=1.0)
    halves = [((0, 0, 0), (11, 22, 22)), ((11, 0, 0), shape)]
    facts = [warpmesh.region_part_facts_read(read, shape, a, b, **options) for a, b in halves]
    with pytest.raises(warpmesh.InputError, match="merge the parts' facts first"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region_facts=facts[0], **part)
    with pytest.raises(warpmesh.InputError, match="a part is missing"):
        warpmesh.merge_region_facts(facts[1:])
    with pytest.raises(warpmesh.InputError, match="given twice"):
        warpmesh.merge_region_facts(facts + facts[:1])
    with pytest.raises(warpmesh.InputError, match="band 6"):
        warpmesh.merge_region_facts([facts[0], warpmesh.region_part_facts_read(read, shape, *halves[1], band=6, **options)])
    facts = warpmesh.merge_region_facts(facts)
    with pytest.raises(warpmesh.InputError, match="not of this part's labels 1, band 6"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region_facts=facts, band=6, **part)
    with pytest.raises(warpmesh.InputError, match="apply to a part"):
        warpmesh.mesh3d_block(volume, (0, 0, 0), (2, 2, 2), region_facts=facts, **options)
    with pytest.raises(warpmesh.InputError, match="does not hold the voxels within"):
        warpmesh.region_part_facts(volume[:11], *halves[0], region=((0, 0, 0), shape), label=1)
    with pytest.raises(warpmesh.InputError, match="no voxel has the label"):
        warpmesh.merge_region_facts([warpmesh.region_part_facts_read(read, shape, (0, 0, 0), shape, label=[1, 9])])
    with pytest.raises(warpmesh.InputError, match="region facts without 'lowest'"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region_facts={k: v for k, v in facts.items() if k != "lowest"},
                              **part)


def test_a_part_needs_listed_materials():
    volume = kmeans_labels()
    with pytest.raises(warpmesh.InputError, match="needs its materials listed"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region=((0, 0, 0), volume.shape), materials="all")
    with pytest.raises(warpmesh.InputError, match="does not lie in the whole"):
        warpmesh.mesh3d_block(volume[:10], (0, 0, 0), (2, 2, 2), region=((15, 0, 0), volume.shape), materials="1,2")


def test_blocks_keep_the_volume_edges_domain_border_tags():
    # Issue 50: faces where the volume's edge cuts a region off are tagged 2
    # (domain_border); blocks flag their vertices the same way, so the merge
    # equals the whole mesh, tags included, for one region and for materials.
    labels = np.zeros((12, 12, 12), np.uint16)
    labels[3:9, 3:9, 0:6] = 1  # against the volume's face x = 0
    labels[3:9, 3:9, 6:9] = 2
    for options in ({"label": 1}, {"materials": "all"}, {"materials": "all", "background": "keep"}):
        whole = warpmesh.mesh3d(labels, **options)
        assert (whole.boundary_tags == 2).sum() > 0, options
        cubes = warpmesh.lattice3d(labels, **options)
        cut = cubes[0] // 2
        blocks = [warpmesh.mesh3d_block(labels, lo, hi, **options)
                  for lo, hi in [((0, 0, 0), (cut, cubes[1], cubes[2])), ((cut, 0, 0), cubes)]]
        assert same(warpmesh.merge_blocks(blocks), whole), options
