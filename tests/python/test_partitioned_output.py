"""Issue 49, item 4: blocks written as a partitioned mesh — a .pvtu and one
.vtu piece per block with global ids — read back by clients nobody on the
team wrote: VTK's XML PUnstructuredGrid reader (the pieces as one mesh, the
shared vertices matched by GlobalIds) and meshio (each piece).  Together the
pieces are the merged mesh: its tetrahedra, regions and points, the points
in the keys' order.  A set of blocks that does not tile is not written."""
import numpy as np
import pytest

import warpmesh
from conftest import require


def labels():
    z, y, x = np.indices((24, 24, 24))
    v = np.zeros((24, 24, 24), np.uint8)
    v[(x - 9) ** 2 + (y - 12) ** 2 + (z - 12) ** 2 < 49] = 1
    v[(x - 16) ** 2 + (y - 12) ** 2 + (z - 12) ** 2 < 36] = 2
    return v


def blocks_of(volume, options):
    cubes = warpmesh.lattice3d(volume, **options)
    halves = [[(0, n // 2), (n // 2, n)] for n in cubes]
    return [warpmesh.mesh3d_block(volume, (x[0], y[0], z[0]), (x[1], y[1], z[1]), **options)
            for x in halves[0] for y in halves[1] for z in halves[2]]


@pytest.mark.parametrize("options, compress", [({"label": "nonzero", "spacing": 1.2}, False),
                                               ({"materials": "1,2", "spacing": 1.0}, True)])
def test_pieces_read_by_vtk_and_meshio_are_the_merged_mesh(tmp_path, options, compress):
    vtk = require("vtk", "python3-vtk9")
    meshio = require("meshio", "python3-meshio")
    from vtk.util.numpy_support import vtk_to_numpy

    volume = labels()
    blocks = blocks_of(volume, options)
    merged = warpmesh.merge_blocks(blocks)
    pieces = warpmesh.write_blocks(tmp_path / "mesh.pvtu", blocks, compress=compress)
    assert pieces == [f"mesh_{i:04d}.vtu" for i in range(8)]

    # VTK: the .pvtu as one grid.
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "mesh.pvtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfCells() == len(merged.tetrahedra)
    point_ids = vtk_to_numpy(grid.GetPointData().GetGlobalIds())
    cell_ids = vtk_to_numpy(grid.GetCellData().GetGlobalIds())
    assert len(np.unique(cell_ids)) == len(cell_ids)
    keys, first = np.unique(point_ids, return_index=True)
    assert len(keys) == len(merged.points)                    # shared vertices: one global id
    points = vtk_to_numpy(grid.GetPoints().GetData())
    assert np.array_equal(points[first], merged.points)       # the merged order is the keys' order
    # Each cell, by global ids, is the merged tetrahedron with the same key.
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
    rank = np.searchsorted(keys, point_ids)
    order = np.argsort(cell_ids)
    assert np.array_equal(rank[conn][order], merged.tetrahedra)
    region = vtk_to_numpy(grid.GetCellData().GetArray("region"))
    assert np.array_equal(region[order], merged.regions)

    # meshio: every piece, its global ids with it.
    total = 0
    for name in pieces:
        m = meshio.read(tmp_path / name)
        ids = m.point_data["GlobalIds"]
        assert np.array_equal(m.points, merged.points[np.searchsorted(keys, ids)])
        total += len(m.cells_dict["tetra"])
    assert total == len(merged.tetrahedra)

    # One piece by itself, and a .pvtu of pieces written one by one.
    warpmesh.write_block(blocks[0], tmp_path / "one.vtu")
    warpmesh.write_pvtu(tmp_path / "one.pvtu", ["one.vtu"])
    reader.SetFileName(str(tmp_path / "one.pvtu"))
    reader.Update()
    assert reader.GetOutput().GetNumberOfCells() == len(blocks[0]["tets"])


def test_blocks_that_do_not_tile_are_not_written(tmp_path):
    blocks = blocks_of(labels(), {"label": "nonzero", "spacing": 1.2})
    with pytest.raises(warpmesh.InputError, match="are in no block"):
        warpmesh.write_blocks(tmp_path / "mesh.pvtu", blocks[1:])
    with pytest.raises(warpmesh.InputError, match="given twice"):
        warpmesh.write_blocks(tmp_path / "mesh.pvtu", blocks + blocks[:1])
    assert not list(tmp_path.iterdir())
    with pytest.raises(warpmesh.InputError, match=r"\.pvtu"):
        warpmesh.write_blocks(tmp_path / "mesh.vtu", blocks)
