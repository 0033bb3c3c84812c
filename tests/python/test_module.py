"""The Python module: numpy arrays, the report, meshio, errors, and the same
meshes as the command line."""
import subprocess
import threading
import time

import numpy as np
import pytest

import warpmesh

BRAIN = "mesher/examples/brain_axial_s128_labels16.pgm"


def test_shape_mesh_has_typed_arrays_and_certified_bounds():
    m = warpmesh.mesh_shape("circle:0,0,1", spacing=0.05)
    assert m.points.dtype == np.float64 and m.points.shape[1] == 2
    assert m.triangles.dtype == np.int32 and m.triangles.shape[1] == 3
    assert m.regions.shape == (len(m.triangles),)
    assert m.boundary_edges.shape == (len(m.boundary_tags), 2)
    assert set(np.unique(m.boundary_tags)) == {1}
    assert m.triangles.min() == 0 and m.triangles.max() == len(m.points) - 1
    # Counter-clockwise, positive area, and the disc's area to within the spacing.
    p = m.points[m.triangles]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    assert (cross > 0).all()
    assert abs(cross.sum() / 2 - np.pi) < 0.05
    lo, hi = m.certified
    assert 0 < lo <= hi < 180
    assert m.certified_min_angle.shape == (len(m.triangles),)
    assert (m.certified_min_angle >= lo).all()
    assert m.report["triangles"] == len(m.triangles)
    assert m.report["certified"]["verified"] is True
    assert "boundary_edges_off_levelset" in m.report["certified"]  # fidelity: analytic shapes


def test_arrays_are_read_only_views_of_the_result_not_copies():
    m = warpmesh.mesh_shape("circle:0,0,1", spacing=0.1)
    t = m.triangles
    assert not t.flags.owndata and not t.flags.writeable
    assert t.base is not None
    assert m.triangles.__array_interface__["data"][0] == t.__array_interface__["data"][0]
    del m  # the view keeps the C++ result alive
    assert t.max() > 0


def test_image_mesh_is_the_cli_mesh(cli, root, tmp_path):
    # Same points (bit for bit), triangles, regions and report as `warpmesh mesh`.
    import meshio

    vtu = tmp_path / "m.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--label", "nonzero", "--spacing", "2", "--graded",
                    "-o", str(vtu), "--quiet"], check=True)
    ref = meshio.read(vtu)
    img = warpmesh.read_image(root / BRAIN)
    m = warpmesh.mesh(img, labels="nonzero", spacing=2, graded=True)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    region = [v for k, v in ref.cell_data_dict.items() if k.lower() in ("region", "regions")]
    assert region and np.array_equal(next(iter(region[0].values())), m.regions)
    assert len(np.unique(m.regions)) > 5  # label tags kept


def test_max_size_and_grading_are_the_cli_options(cli, tmp_path):
    # The kwargs give the CLI's mesh; every edge is <= max_size; bad values
    # raise ValueError with the CLI's message.
    import meshio

    vtu = tmp_path / "g.vtu"
    subprocess.run([cli, "mesh", "--shape", "circle:0,0,40", "--graded", "--max-size", "6", "--grading", "1.5",
                    "-o", str(vtu), "--quiet"], check=True)
    ref = meshio.read(vtu)
    m = warpmesh.mesh_shape("circle:0,0,40", graded=True, max_size=6, grading=1.5)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    p = m.points[m.triangles]
    longest = max(np.linalg.norm(p[:, k] - p[:, (k + 1) % 3], axis=1).max() for k in range(3))
    assert longest <= 6
    assert m.report["max_cell"] == 4 and m.report["grading_buffer"] == 2  # √2·4 <= 6 < √2·8
    plain = warpmesh.mesh_shape("circle:0,0,40", graded=True)
    assert len(plain.triangles) < len(m.triangles)
    assert "max_cell" not in plain.report  # default reports unchanged
    with pytest.raises(ValueError, match="--grading must be between 1.1 and 2"):
        warpmesh.mesh_shape("circle:0,0,40", graded=True, grading=3)
    with pytest.raises(ValueError, match="below sqrt\\(5\\) \\* spacing"):
        warpmesh.mesh_shape("circle:0,0,40", max_size=1)


def test_threshold_default_iso_is_half_maxval_like_the_cli(cli, root, tmp_path):
    path = root / "tests/data/horse_binary.pgm"
    rep = tmp_path / "r.json"
    subprocess.run([cli, "mesh", str(path), "--spacing", "4", "--report", str(rep), "--quiet"], check=True)
    import json

    ref = json.loads(rep.read_text())
    m = warpmesh.mesh(warpmesh.read_image(path), spacing=4)
    for key in ("triangles", "vertices", "boundary_edges", "levelset", "lattice"):
        assert m.report[key] == ref[key], key


def test_numpy_arrays_uint8_bool_and_labels():
    img = np.zeros((40, 50), np.uint8)
    img[10:30, 5:25] = 200
    img[12:28, 30:45] = 100
    a = warpmesh.mesh(img)  # iso 127.5: the bright block only
    b = warpmesh.mesh(img > 0)  # bool: both blocks
    assert 0 < len(a.triangles) < len(b.triangles)
    c = warpmesh.mesh(img, labels=[100, 200])
    assert set(np.unique(c.regions)) == {100, 200}
    d = warpmesh.mesh(img, iso=50, inside="below", spacing=2)
    assert len(d.triangles) > 0
    assert set(np.unique(d.boundary_tags)) == {1, 2}  # the outside touches the image border


def test_pixel_size_scales_coordinates_only():
    img = np.zeros((30, 30), np.uint8)
    img[5:25, 5:25] = 255
    a = warpmesh.mesh(img)
    b = warpmesh.mesh(img, pixel_size=0.5)
    assert np.array_equal(b.points, a.points * 0.5)
    assert np.array_equal(a.triangles, b.triangles)
    with pytest.raises(ValueError, match="pixel_size"):
        warpmesh.mesh(img, pixel_size=(0.5, 1.0))


def test_bad_input_raises_value_error_naming_the_problem():
    img = np.zeros((20, 20), np.uint8)
    with pytest.raises(ValueError, match="region is empty"):
        warpmesh.mesh(img, iso=10)
    with pytest.raises(ValueError, match="none of the labels"):
        warpmesh.mesh(img, labels=7)
    with pytest.raises(ValueError, match="at least 2 x 2"):
        warpmesh.mesh(np.ones((1, 9), np.uint8))
    with pytest.raises(ValueError, match="max-squares"):
        warpmesh.mesh_shape("circle:0,0,10", spacing=1e-4)
    with pytest.raises(ValueError, match="spacing"):
        warpmesh.mesh_shape("circle:0,0,10", spacing=-1)
    with pytest.raises(ValueError, match="circle"):
        warpmesh.mesh_shape("circle:0,0")
    with pytest.raises(TypeError, match="float"):
        warpmesh.mesh(np.zeros((5, 5)))
    with pytest.raises(warpmesh.InputError):
        warpmesh.read_image("/nonexistent.pgm")


def test_guarantee_flat_refines_and_warns_when_it_stops(root):
    img = warpmesh.read_image(root / "tests/data/K1_small.pgm")
    with pytest.warns(RuntimeWarning, match="still not flat"):
        m = warpmesh.mesh(img, iso=128, spacing=16, guarantee="flat")
    assert m.refinements == 4 and m.spacing == 1
    assert m.report["refinements"] == 4


def test_read_image_returns_the_pixels_with_maxval(root):
    img = warpmesh.read_image(root / BRAIN)
    assert img.dtype == np.uint16 and img.shape == (256, 256)
    assert img.maxval >= img.max() > 0
    with pytest.raises(ValueError, match="slice"):
        warpmesh.read_image(root / BRAIN, slice=3)


def write_nrrd(path, data):
    """A raw little-endian uint16 NRRD of a (k, j, i) array (i fastest)."""
    k, j, i = data.shape
    with open(path, "wb") as f:
        f.write(b"NRRD0004\ntype: unsigned short\ndimension: 3\nsizes: %d %d %d\nencoding: raw\nendian: little\n\n"
                % (i, j, k))
        f.write(np.ascontiguousarray(data, dtype="<u2").tobytes())


def test_read_image_takes_a_slice_of_a_volume_as_the_cli_meshes_it(cli, tmp_path):
    # A 3-slice label volume: slice k=1 comes back with i along the columns and
    # j upwards, and meshes to exactly the CLI's `--slice k=1 --units pixels` mesh.
    import meshio

    yy, xx = np.mgrid[0:14, 0:17]
    data = np.stack([((xx - 8) ** 2 + (yy - 6) ** 2 < r * r).astype(np.uint16) * (r - 2) for r in (3, 5, 6)])
    vol = tmp_path / "v.nrrd"
    write_nrrd(vol, data)
    img = warpmesh.read_image(vol, slice="k=1")
    assert img.shape == (14, 17) and np.array_equal(img, data[1, ::-1, :])
    with pytest.raises(ValueError, match="choose a slice"):
        warpmesh.read_image(vol)
    with pytest.raises(ValueError, match="outside"):
        warpmesh.read_image(vol, slice="k=3")
    vtu = tmp_path / "s.vtu"
    subprocess.run([cli, "mesh", str(vol), "--slice", "k=1", "--units", "pixels", "--label", "3",
                    "-o", str(vtu), "--quiet"], check=True)
    ref = meshio.read(vtu)
    m = warpmesh.mesh(img, labels=[3])
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)


def test_materials_mesh_is_the_cli_multi_material_mesh(cli, root, tmp_path):
    import meshio

    vtu = tmp_path / "mm.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--materials", "all", "--spacing", "2", "-o", str(vtu), "--quiet"],
                   check=True, capture_output=True)
    ref = meshio.read(vtu)
    img = warpmesh.read_image(root / BRAIN)
    m = warpmesh.mesh(img, materials="all", spacing=2)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    assert len(np.unique(m.regions)) > 20 and 0 not in m.regions  # every label; background dropped
    assert len(m.interfaces) > 0 and len(m.interface_regions) == len(m.interfaces)
    kept = warpmesh.mesh(img, materials=[41, 43], background="keep", spacing=2)
    assert set(np.unique(kept.regions)) == {0, 41, 43}
    with pytest.raises(ValueError, match="12345"):
        warpmesh.mesh(img, materials=[41, 12345], spacing=2)
    with pytest.raises(ValueError, match="exclude"):
        warpmesh.mesh(img, materials="all", labels=[41])


def test_graded_materials_mesh_is_the_cli_graded_multi_material_mesh(cli, root, tmp_path):
    import meshio

    vtu = tmp_path / "mmg.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--materials", "all", "--graded", "--verify", "--spacing", "1",
                    "-o", str(vtu), "--quiet"], check=True, capture_output=True)
    ref = meshio.read(vtu)
    img = warpmesh.read_image(root / BRAIN)
    g = warpmesh.mesh(img, materials="all", graded=True, spacing=1)
    u = warpmesh.mesh(img, materials="all", spacing=1)
    assert np.array_equal(ref.points[:, :2], g.points)
    assert np.array_equal(ref.cells_dict["triangle"], g.triangles)
    assert len(g.triangles) < len(u.triangles)
    # The same interfaces (as coordinate pairs, with the regions on either side).
    def keyed(m):
        out = set()
        for (a, b), (l, r) in zip(m.interfaces, m.interface_regions):
            pa, pb = tuple(m.points[a]), tuple(m.points[b])
            out.add((pa, pb, int(l), int(r)) if pa < pb else (pb, pa, int(r), int(l)))
        return out
    assert keyed(g) == keyed(u) and len(keyed(g)) > 1000


def test_max_size_of_caps_one_label_like_the_cli(cli, root, tmp_path):
    # max_size_of={label: size} is --max-size-of label=size: the CLI's mesh,
    # read back by meshio; that label's edges are <= size, the report gives
    # its cap and longest edge; a label that is no material is a ValueError.
    import meshio

    vtu = tmp_path / "cap.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--materials", "all", "--graded", "--spacing", "1",
                    "--max-size-of", "41=2.5", "--grading", "1.5", "-o", str(vtu), "--quiet"], check=True,
                   capture_output=True)
    ref = meshio.read(vtu)
    img = warpmesh.read_image(root / BRAIN)
    m = warpmesh.mesh(img, materials="all", graded=True, spacing=1, max_size_of={41: 2.5}, grading=1.5)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    p = m.points[m.triangles[m.regions == 41]]
    longest = max(np.linalg.norm(p[:, k] - p[:, (k + 1) % 3], axis=1).max() for k in range(3))
    assert longest <= 2.5
    entry = next(e for e in m.report["materials"] if e["tag"] == 41)
    assert entry["max_size"] == 2.5 and entry["longest_edge"] == pytest.approx(longest, rel=1e-12)
    assert m.report["max_size_of"] == [{"tag": 41, "max_size": 2.5, "max_cell": 1}]  # √2 <= 2.5 < √2·2
    plain = warpmesh.mesh(img, materials="all", graded=True, spacing=1, grading=1.5)
    assert (plain.regions == 41).sum() < (m.regions == 41).sum()
    assert "max_size_of" not in plain.report
    with pytest.raises(ValueError, match="no material has tag 12345"):
        warpmesh.mesh(img, materials="all", graded=True, max_size_of={12345: 3})
    with pytest.raises(ValueError, match="max_size_of applies to multi-material meshes"):
        warpmesh.mesh(img, labels="nonzero", graded=True, max_size_of={41: 3})


def test_to_meshio_and_back_through_a_file(tmp_path):
    import meshio

    m = warpmesh.mesh_shape("annulus:0,0,1,2", spacing=0.1)
    mm = m.to_meshio()
    assert np.array_equal(mm.cells_dict["triangle"], m.triangles)
    assert set(mm.cell_data) == {"region", "certified_min_angle"}
    mm.write(tmp_path / "a.vtu")
    back = meshio.read(tmp_path / "a.vtu")
    assert np.array_equal(back.cell_data["certified_min_angle"][0], m.certified_min_angle)
    with_boundary = m.to_meshio(boundary=True)
    assert np.array_equal(with_boundary.cells_dict["line"], m.boundary_edges)
    m.write(tmp_path / "b.vtu")  # warpmesh's own writer
    assert np.array_equal(meshio.read(tmp_path / "b.vtu").cells_dict["triangle"], m.triangles)


def test_meshing_releases_the_gil():
    # While one thread meshes, another keeps running Python code.
    done = threading.Event()
    result = {}

    def work():
        result["m"] = warpmesh.mesh_shape("flower:0,0,300,100,5", spacing=0.25, threads=1)
        done.set()

    t = threading.Thread(target=work)
    t0 = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0)
    t.join()
    elapsed = time.perf_counter() - t0
    assert elapsed > 0.05, "the meshing was too quick to tell"
    assert ticks > 100, f"the main thread ran {ticks} times in {elapsed:.3f} s"


def test_write_uses_the_fast_writers_in_every_form(tmp_path):
    """warpmesh.write(result, path, ...) writes with the CLI's writers: binary
    by default, zlib .vtu, text with ascii=True, inline XDMF; meshio reads
    every form back to the same mesh; to_meshio() is unchanged."""
    import meshio

    m = warpmesh.mesh_shape("annulus:0,0,1,2", spacing=0.1)
    forms = {"raw.vtu": {}, "zlib.vtu": {"compress": True}, "text.vtu": {"ascii": True}, "bin.msh": {},
             "text.msh": {"ascii": True}, "h5.xdmf": {}, "inline.xdmf": {"xdmf_inline": True}}
    for name, kw in forms.items():
        warpmesh.write(m, tmp_path / name, **kw)
        back = meshio.read(tmp_path / name)
        assert np.array_equal(back.points[:, :2], m.points), name
        assert np.array_equal(back.cells_dict["triangle"], m.triangles), name
    assert (tmp_path / "h5.h5").exists() and (tmp_path / "h5_facets.h5").exists()
    assert not (tmp_path / "inline.h5").exists()
    assert b"appended" in (tmp_path / "raw.vtu").read_bytes()[:2000]
    assert b"vtkZLibDataCompressor" in (tmp_path / "zlib.vtu").read_bytes()[:2000]
    assert (tmp_path / "bin.msh").read_bytes().startswith(b"$MeshFormat\n4.1 1 8\n")
    assert (tmp_path / "text.msh").read_bytes().startswith(b"$MeshFormat\n4.1 0 8\n")
    with pytest.raises(warpmesh.OutputError):
        warpmesh.write(m, tmp_path / "no-such-dir" / "x.vtu")
