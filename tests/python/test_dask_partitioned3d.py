"""Issue 49, item 5 (small): examples/dask_partitioned3d.py meshes a label
volume stored as chunked zarr on a dask LocalCluster of two memory-limited
process workers, each block from its part only (no block reads 60 % of the
volume), each piece written by the worker that made it and the .pvtu by the
driver from the pieces' metadata.  Read back by VTK's
PUnstructuredGrid reader and by meshio, the pieces are the single-process
mesh: tetrahedra, volume per material, and vertices by GlobalIds.  A lost
piece and bad input are refused with a clear error."""
import importlib.util
import os

import numpy as np
import pytest

import warpmesh
from conftest import require

OPTIONS = {"materials": "1,2,4", "spacing": 1.1, "voxel_size": (1.0, 1.0, 1.25)}


def load_example(root):
    spec = importlib.util.spec_from_file_location("dask_partitioned3d", root / "examples" / "dask_partitioned3d.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def kmeans_labels(n=32, k=4, seed=5):
    """Labels 1..k of the nearest of k random centres inside a ball, 0 outside."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(3, n - 3, size=(k, 3))
    z, y, x = np.indices((n, n, n)).astype(float)
    v = (np.argmin([(x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2 for c in centres], axis=0) + 1).astype(np.int16)
    v[(x - n / 2) ** 2 + (y - n / 2) ** 2 + (z - n / 2) ** 2 > (0.42 * n) ** 2] = 0
    return v


def read_pvtu(vtk, path):
    """The .pvtu at `path` as VTK's PUnstructuredGrid reader reads it: the
    grid, its points' distinct GlobalIds (keys), the points in the keys'
    order and the tetrahedra numbered so."""
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    point_ids = vtk_to_numpy(grid.GetPointData().GetGlobalIds())
    keys, first = np.unique(point_ids, return_index=True)
    tets = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
    return grid, keys, vtk_to_numpy(grid.GetPoints().GetData())[first], np.searchsorted(keys, point_ids)[tets]


def tet_volumes(points, tets):
    p = points[tets]
    return np.abs(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])) / 6


@pytest.fixture(scope="module")
def client():
    distributed = require("distributed", "python3-distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, memory_limit="1GB",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def test_pieces_made_on_workers_are_the_single_process_mesh(root, tmp_path, client):
    vtk = require("vtk", "python3-vtk9")
    meshio = require("meshio", "python3-meshio")
    zarr = require("zarr", "python3-zarr")
    from vtk.util.numpy_support import vtk_to_numpy

    mod = load_example(root)
    labels = kmeans_labels()
    path = tmp_path / "labels.zarr"
    zarr.open_array(str(path), mode="w", shape=labels.shape, chunks=(8, 8, 8), dtype=labels.dtype)[:] = labels
    done = []
    pieces, workers = mod.mesh_partitioned(client, path, tmp_path / "mesh.pvtu", 17,
                                         lambda i, n: done.append((i, n)), **OPTIONS)
    whole = warpmesh.mesh3d(labels, **OPTIONS)
    assert len(pieces) == len(done) == done[-1][0] == done[-1][1] == 12
    assert len(client.scheduler_info()["workers"]) == 2 and os.getpid() not in workers  # process workers
    assert max(p["voxels_read"] for p in pieces) < 0.6 * labels.size
    assert sum(p["tetrahedra"] for p in pieces) == len(whole.tetrahedra) > 1000

    # VTK: the .pvtu as one mesh, its vertices numbered as the whole mesh's (by GlobalIds).
    grid, keys, points, tets = read_pvtu(vtk, tmp_path / "mesh.pvtu")
    assert len(keys) == len(whole.points) and np.array_equal(points, whole.points)
    region = vtk_to_numpy(grid.GetCellData().GetArray("region"))
    cell_ids = vtk_to_numpy(grid.GetCellData().GetGlobalIds())
    assert len(tets) == len(whole.tetrahedra) and len(np.unique(cell_ids)) == len(cell_ids)
    assert np.array_equal(np.sort(np.sort(tets, axis=1), axis=0), np.sort(np.sort(whole.tetrahedra, axis=1), axis=0))
    volume, whole_volume = tet_volumes(points, tets), tet_volumes(whole.points, whole.tetrahedra)
    for tag in (1, 2, 4):
        assert np.isclose(volume[region == tag].sum(), whole_volume[whole.regions == tag].sum(), rtol=1e-12)

    # meshio: every piece with tetrahedra (its reader fails on a .vtu of no
    # cells), its vertices by GlobalIds.
    total = 0
    for p in (p for p in pieces if p["tetrahedra"]):
        m = meshio.read(p["piece"])
        assert np.array_equal(m.points, whole.points[np.searchsorted(keys, m.point_data["GlobalIds"])])
        total += len(m.cells_dict["tetra"])
    assert total == len(whole.tetrahedra)

    # A lost piece (a failed task) is refused, nothing written.
    with pytest.raises(warpmesh.InputError, match="are in no block"):
        warpmesh.write_pvtu(tmp_path / "lost.pvtu", pieces[:3] + pieces[4:])
    with pytest.raises(warpmesh.InputError, match="given twice"):
        warpmesh.write_pvtu(tmp_path / "twice.pvtu", pieces + pieces[:1])
    assert not (tmp_path / "lost.pvtu").exists() and not (tmp_path / "twice.pvtu").exists()


def test_one_region_pieces_after_the_workers_reduction_are_the_single_process_mesh(root, tmp_path, client):
    """One region (label=): the workers first reduce parts of the volume to
    the whole region's facts, then mesh their blocks from their parts; the
    pieces' vertices (by GlobalIds) and tetrahedra are the single-process
    mesh's."""
    vtk = require("vtk", "python3-vtk9")
    mod = load_example(root)
    labels, options = kmeans_labels(24), {"label": "1,2", "spacing": 1.1, "voxel_size": (1.0, 1.0, 1.25)}
    np.save(tmp_path / "labels.npy", labels)
    pieces, _ = mod.mesh_partitioned(client, tmp_path / "labels.npy", tmp_path / "one.pvtu", 12, **options)
    whole = warpmesh.mesh3d(labels, **options)
    _, keys, points, tets = read_pvtu(vtk, tmp_path / "one.pvtu")
    assert len(keys) == len(whole.points) and np.array_equal(points, whole.points)
    assert len(pieces) > 4 and len(tets) == len(whole.tetrahedra) > 1000
    assert np.array_equal(np.sort(np.sort(tets, axis=1), axis=0), np.sort(np.sort(whole.tetrahedra, axis=1), axis=0))


def test_bad_input_is_refused_clearly(root, tmp_path, client):
    mod = load_example(root)
    with pytest.raises(warpmesh.InputError, match="no volume at"):
        mod.mesh_partitioned(client, tmp_path / "missing.npy", tmp_path / "m.pvtu", 8, **OPTIONS)
    np.save(tmp_path / "float.npy", kmeans_labels().astype(np.float32))
    with pytest.raises(warpmesh.InputError, match="give 3D integer labels"):
        mod.mesh_partitioned(client, tmp_path / "float.npy", tmp_path / "m.pvtu", 8, **OPTIONS)
    np.save(tmp_path / "labels.npy", kmeans_labels(8))
    with pytest.raises(warpmesh.InputError, match="at least 1 cube"):
        mod.mesh_partitioned(client, tmp_path / "labels.npy", tmp_path / "m.pvtu", 0, **OPTIONS)
    # Pieces of two different meshes (another spacing) do not make one.
    labels, other = kmeans_labels(16), dict(OPTIONS, spacing=1.2)
    cubes, other_cubes = warpmesh.lattice3d(labels, **OPTIONS), warpmesh.lattice3d(labels, **other)
    a = warpmesh.mesh3d_block(labels, (0, 0, 0), (cubes[0] // 2, cubes[1], cubes[2]), **OPTIONS)
    b = warpmesh.mesh3d_block(labels, (cubes[0] // 2, 0, 0), other_cubes, **other)
    pieces = [warpmesh.write_block(a, tmp_path / "a.vtu"), warpmesh.write_block(b, tmp_path / "b.vtu")]
    with pytest.raises(warpmesh.InputError, match="different"):
        warpmesh.write_pvtu(tmp_path / "mixed.pvtu", pieces)
    with pytest.raises(warpmesh.InputError, match="empty list"):
        warpmesh.write_pvtu(tmp_path / "none.pvtu", [])


def test_a_piece_without_tetrahedra_has_the_global_ids_its_pvtu_declares(tmp_path):
    """634 of the 729 blocks of the SPL brain's eight materials at 1024^3
    have no tetrahedron; their pieces lacked the GlobalIds arrays the .pvtu
    declares, and VTK's reader logged an error for each."""
    vtk = require("vtk", "python3-vtk9")
    block = warpmesh.mesh3d_block(kmeans_labels(16), (0, 0, 0), (1, 1, 1), **OPTIONS)
    assert len(block["tets"]) == 0
    warpmesh.write_block(block, tmp_path / "empty.vtu")
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "empty.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetPointData().GetArray("GlobalIds") is not None
    assert grid.GetCellData().GetArray("GlobalIds") is not None
