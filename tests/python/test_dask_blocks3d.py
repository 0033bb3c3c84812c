"""examples/dask_blocks3d.py (issue 30, item 6): a label volume meshed in
blocks on a dask LocalCluster merges into exactly the single-process mesh —
points, tetrahedra, boundary faces and tags, bit for bit — for two block
sizes and either worker count, and for a shape in any block order; a block
given twice and a block outside the lattice are refused."""
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
