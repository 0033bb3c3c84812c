"""The Python module: numpy arrays, the report, meshio, errors, and the same
meshes as the command line."""
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import warpmesh

BRAIN = "mesher/examples/brain_axial_s128_labels16.pgm"
BRAIN_PATH = str(pathlib.Path(__file__).resolve().parents[2] / BRAIN)


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
    # The library's words name the keyword, not the CLI's flag (issue 46).
    with pytest.raises(ValueError, match="^grading must be between 1.1 and 2"):
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
    with pytest.raises(ValueError, match="max_squares"):
        warpmesh.mesh_shape("circle:0,0,10", spacing=1e-4)
    with pytest.raises(ValueError, match="spacing"):
        warpmesh.mesh_shape("circle:0,0,10", spacing=-1)
    with pytest.raises(ValueError, match="circle"):
        warpmesh.mesh_shape("circle:0,0")
    with pytest.raises(warpmesh.InputError, match="float"):
        warpmesh.mesh(np.zeros((5, 5)))
    with pytest.raises(warpmesh.InputError):
        warpmesh.read_image("/nonexistent.pgm")


IMG = np.zeros((20, 20), np.uint8)
IMG[5:15, 5:15] = 200

# Issue 27: warpmesh.mesh(float_image) raised TypeError where the README
# promises ValueError / warpmesh.InputError.  Every bad input, of any kind
# (wrong type, wrong value, contradictory options), raises InputError.
BAD_INPUTS = [
    ("float image", lambda: warpmesh.mesh(np.zeros((5, 5)))),
    ("complex image", lambda: warpmesh.mesh(np.zeros((5, 5), complex))),
    ("object image", lambda: warpmesh.mesh(np.array([[None, 1], [2, 3]], dtype=object))),
    ("string image", lambda: warpmesh.mesh("picture.png")),
    ("ragged image", lambda: warpmesh.mesh([[1, 2], [3]])),
    ("3D image", lambda: warpmesh.mesh(np.zeros((3, 4, 5), np.uint8))),
    ("negative values", lambda: warpmesh.mesh(np.full((5, 5), -1))),
    ("values over 65535", lambda: warpmesh.mesh(np.full((5, 5), 70000))),
    ("inside", lambda: warpmesh.mesh(IMG, inside="up")),
    ("iso and labels", lambda: warpmesh.mesh(IMG, iso=3, labels=1)),
    ("iso not a number", lambda: warpmesh.mesh(IMG, iso="half")),
    ("labels not integers", lambda: warpmesh.mesh(IMG, labels=[1.5])),
    ("labels bad string", lambda: warpmesh.mesh(IMG, labels="a-b")),
    ("labels object", lambda: warpmesh.mesh(IMG, labels=object())),
    ("materials not integers", lambda: warpmesh.mesh(IMG, materials=[200.5])),
    ("materials and labels", lambda: warpmesh.mesh(IMG, materials="all", labels=200)),
    ("background", lambda: warpmesh.mesh(IMG, materials="all", background="hide")),
    ("spacing not a number", lambda: warpmesh.mesh(IMG, spacing="fine")),
    ("spacing nan", lambda: warpmesh.mesh(IMG, spacing=float("nan"))),
    ("spacing negative", lambda: warpmesh.mesh(IMG, spacing=-1)),
    ("pixel_size", lambda: warpmesh.mesh(IMG, pixel_size="big")),
    ("pixel_size anisotropic", lambda: warpmesh.mesh(IMG, pixel_size=(0.5, 1.0))),
    ("max_cell not an integer", lambda: warpmesh.mesh(IMG, graded=True, max_cell=1.5)),
    ("max_cell not a power of two", lambda: warpmesh.mesh(IMG, graded=True, max_cell=3)),
    ("max_cell without graded", lambda: warpmesh.mesh(IMG, max_cell=4)),
    ("grading without graded", lambda: warpmesh.mesh(IMG, grading=1.5)),
    ("grading out of range", lambda: warpmesh.mesh(IMG, graded=True, grading=3)),
    ("max_size 0", lambda: warpmesh.mesh(IMG, max_size=0)),
    ("max_size not a number", lambda: warpmesh.mesh(IMG, max_size=[3])),
    ("max_size_of not a dict", lambda: warpmesh.mesh(IMG, materials="all", max_size_of=[(200, 3)])),
    ("max_size_of bad size", lambda: warpmesh.mesh(IMG, materials="all", max_size_of={200: "big"})),
    ("rule", lambda: warpmesh.mesh(IMG, rule="delaunay")),
    ("guarantee", lambda: warpmesh.mesh(IMG, guarantee="always")),
    ("max_squares not an integer", lambda: warpmesh.mesh(IMG, max_squares="many")),
    ("threads zero", lambda: warpmesh.mesh(IMG, threads=0)),
    ("threads not an integer", lambda: warpmesh.mesh(IMG, threads="all")),
    ("empty region", lambda: warpmesh.mesh(IMG, iso=250)),
    ("shape not a string", lambda: warpmesh.mesh_shape(3)),
    ("bad shape", lambda: warpmesh.mesh_shape("circle:0,0")),
    ("shape spacing", lambda: warpmesh.mesh_shape("circle:0,0,1", spacing=None)),
    ("read_image missing file", lambda: warpmesh.read_image("/nonexistent.pgm")),
    ("read_image units", lambda: warpmesh.read_image("/nonexistent.pgm", units="inch")),
    ("read_image mm without a pixel size", lambda: warpmesh.read_image(BRAIN_PATH, units="mm")),
    ("read_image max_pixels", lambda: warpmesh.read_image("/nonexistent.pgm", max_pixels="lots")),
    ("max_memory not an integer", lambda: warpmesh.mesh(IMG, max_memory="lots")),
    ("max_memory zero", lambda: warpmesh.mesh(IMG, materials="all", max_memory=0)),
    ("max_memory too small for the lattice", lambda: warpmesh.mesh_shape("circle:0,0,1", spacing=1e-4, max_memory=1)),
    ("read_image max_memory", lambda: warpmesh.read_image(BRAIN_PATH, max_memory=-1)),
    ("shapes not a string", lambda: warpmesh.mesh_shapes(["1=circle:0,0,1"])),
    ("bad shapes", lambda: warpmesh.mesh_shapes("1=circle:0,0")),
    ("shapes background", lambda: warpmesh.mesh_shapes("1=circle:0,0,1", background="hide")),
    ("shapes max_memory", lambda: warpmesh.mesh_shapes("1=circle:0,0,1", spacing=1e-4, max_memory=1)),
]


@pytest.mark.parametrize("what, call", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_every_bad_input_raises_input_error(what, call):
    with pytest.raises(warpmesh.InputError) as e:
        call()
    assert issubclass(e.type, ValueError) and str(e.value), what


def test_fan_rule_is_the_cli_diagonal_fan(cli, root, tmp_path):
    # Issue 27: rule="fan" was refused by the module although the CLI has
    # --diagonal fan.  The same mesh, point for point, and its certificate.
    import meshio

    vtu = tmp_path / "fan.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--label", "nonzero", "--diagonal", "fan", "--spacing", "2",
                    "-o", str(vtu), "--quiet"], check=True)
    ref = meshio.read(vtu)
    m = warpmesh.mesh(warpmesh.read_image(root / BRAIN), labels="nonzero", rule="fan", spacing=2)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    assert m.report["rule"] == "fan" and m.certified[0] >= 18.4349
    s = warpmesh.mesh_shape("circle:0,0,20", rule="fan", graded=True)
    assert s.certified[0] >= 18.4349


def test_fan_rule_with_materials_is_the_cli_and_certifies_18_4(cli, root, tmp_path):
    # Issue 28: rule="fan" / --diagonal fan were refused with materials.  Now
    # the same mesh point for point, tags included, and the unconditional
    # floor 18.4349 deg holds, junction squares included (uniform and graded).
    import meshio

    vtu = tmp_path / "fan_materials.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--materials", "all", "--diagonal", "fan", "-o", str(vtu), "--quiet"],
                   check=True)
    ref = meshio.read(vtu)
    m = warpmesh.mesh(warpmesh.read_image(root / BRAIN), materials="all", rule="fan")
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    assert m.report["rule"] == "fan" and m.certified[0] >= 18.4349
    assert m.report["junction_squares"]["count"] > 0
    g = warpmesh.mesh(warpmesh.read_image(root / BRAIN), materials="all", rule="fan", graded=True)
    assert g.certified[0] >= 18.4349


def write_nrrd_mm(path, data, directions, origin):
    """A raw uint16 NRRD of a (k, j, i) array with space directions (one
    3-vector per index axis i, j, k) and origin, in millimetres."""
    k, j, i = data.shape
    fmt = lambda v: "(" + ",".join(repr(float(x)) for x in v) + ")"
    with open(path, "wb") as f:
        f.write(b"NRRD0004\ntype: unsigned short\ndimension: 3\nsizes: %d %d %d\nencoding: raw\nendian: little\n"
                % (i, j, k))
        f.write(("space: left-posterior-superior\nspace directions: " + " ".join(map(fmt, directions)) +
                 "\nspace origin: " + fmt(origin) + "\n\n").encode())
        f.write(np.ascontiguousarray(data, dtype="<u2").tobytes())


def test_read_image_slice_in_millimetres_meshes_like_the_cli(cli, tmp_path):
    # Issue 28: read_image(..., slice=...) of a volume with anisotropic
    # pixels in physical units.  A permuted NRRD (i along y at 0.5 mm, j along
    # x at 1.5 mm): the Image's geometry is the CLI's, mesh() gives the CLI's
    # `--slice k=1` mesh in millimetres point for point (one region and
    # materials), per-label areas are pixel counts x 0.75 mm^2 within the
    # discretisation error, and units="pixels" gives the pixel-unit mesh.
    import meshio

    yy, xx = np.mgrid[0:40, 0:48]
    data = np.zeros((3, 40, 48), np.uint16)
    for k in range(3):
        data[k][((xx - 20) / 12.0) ** 2 + ((yy - 20) / 9.0) ** 2 < 1] = 2
        data[k][(xx - 20) ** 2 + (yy - 20) ** 2 < 16 + 4 * k] = 7
        data[k][(xx > 36) & (xx < 45) & (yy > 5) & (yy < 30)] = 40
    vol = tmp_path / "v.nrrd"
    write_nrrd_mm(vol, data, [(0, 0.5, 0), (1.5, 0, 0), (0, 0, 2)], (10, -20, 5))
    img = warpmesh.read_image(vol, slice="k=1")
    assert img.units == "mm"
    assert img.geometry == (-20.0, 10.0, 0.5, 1.5)  # origin . y, origin . x; the pixel sizes
    assert img.plane["origin"] == (0.0, 0.0, 7.0) and img.plane["x_axis"] == (0.0, 1.0, 0.0)
    for kwargs, args in ((dict(labels=[2, 7]), ["--label", "2,7"]), (dict(materials="all"), ["--materials", "all"])):
        vtu = tmp_path / "ref.vtu"
        subprocess.run([cli, "mesh", str(vol), "--slice", "k=1", *args, "-o", str(vtu), "--quiet"], check=True)
        ref = meshio.read(vtu)
        m = warpmesh.mesh(img, **kwargs)
        assert np.array_equal(ref.points[:, :2], m.points), args
        assert np.array_equal(ref.cells_dict["triangle"], m.triangles), args
        assert m.spacing == 0.5  # the smaller pixel size, as the CLI's default
    m = warpmesh.mesh(img, materials="all")
    p = m.points[m.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    for label in (2, 7, 40):
        want = (img == label).sum() * 0.75
        assert abs(area[m.regions == label].sum() - want) < 0.05 * want, label
    entry = {e["tag"]: e for e in m.report["materials"]}
    assert entry[40]["pixel_area"] == (img == 40).sum() * 0.75
    px = warpmesh.read_image(vol, slice="k=1", units="pixels")
    assert px.units == "pixels" and px.geometry is None and np.array_equal(px, img)
    vtu = tmp_path / "px.vtu"
    subprocess.run([cli, "mesh", str(vol), "--slice", "k=1", "--units", "pixels", "--materials", "all",
                    "-o", str(vtu), "--quiet"], check=True)
    assert np.array_equal(meshio.read(vtu).points[:, :2], warpmesh.mesh(px, materials="all").points)
    with pytest.raises(warpmesh.InputError, match="pixel_size"):
        warpmesh.mesh(img, pixel_size=2)


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


def test_fan_rule_is_accepted_like_the_cli_python_wrapper_refused_it():
    # The wrapper once accepted only "separating" and "maxmin", although the
    # C++ module and the CLI take --diagonal fan: its certified floor is
    # atan(1/3) on every input.
    m = warpmesh.mesh_shape("circle:0,0,1", spacing=0.05, rule="fan")
    assert m.report["rule"] == "fan"
    assert m.certified[0] > 18.4349
    with pytest.raises(ValueError, match="'separating', 'maxmin' or 'fan'"):
        warpmesh.mesh_shape("circle:0,0,1", rule="delaunay")


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


# Issue 28: --optimize with materials and --shapes from Python, point for
# point the CLI's mesh; max_memory on every entry point.
@pytest.mark.parametrize("graded", [False, True])
def test_optimize_with_materials_is_the_cli_optimize(cli, root, tmp_path, graded):
    import meshio

    vtu = tmp_path / "mo.vtu"
    subprocess.run([cli, "mesh", str(root / BRAIN), "--materials", "all", "--spacing", "2", "--optimize",
                    *(["--graded"] if graded else []), "-o", str(vtu), "--quiet"], check=True, capture_output=True)
    ref = meshio.read(vtu)
    img = warpmesh.read_image(root / BRAIN)
    m = warpmesh.mesh(img, materials="all", spacing=2, graded=graded, optimize=True)
    plain = warpmesh.mesh(img, materials="all", spacing=2, graded=graded)
    assert np.array_equal(ref.points[:, :2], m.points)
    assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
    o = m.report["optimize"]
    assert o["min_angle_after_deg"] > o["min_angle_before_deg"] == plain.report["min_angle_deg"]
    assert o["max_angle_after_deg"] <= o["max_angle_before_deg"]
    # No label's area error against its pixel count grew.
    before = {x["tag"]: abs(x["area_minus_pixel_area"]) for x in plain.report["materials"] if x["output"]}
    areas = {x["tag"]: x["area"] for x in plain.report["materials"]}
    for x in m.report["materials"]:
        if x["output"]:
            assert abs(x["area_minus_pixel_area"]) <= before[x["tag"]] + 1e-9 * x["pixel_area"], x
            assert abs(x["area_before_optimize"] - areas[x["tag"]]) <= 1e-9 * x["pixel_area"], x  # reported before/after
    assert "optimize" not in plain.report
    assert all("area_before_optimize" not in x for x in plain.report["materials"])


def test_mesh_shapes_is_the_cli_shapes_mesh_with_and_without_optimize(cli, tmp_path):
    import meshio

    spec = "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12"
    for extra, kw in (([], {}), (["--optimize", "--background", "keep"], dict(optimize=True, background="keep"))):
        vtu = tmp_path / "s.vtu"
        subprocess.run([cli, "mesh", "--shapes", spec, "--spacing", "0.5", *extra, "-o", str(vtu), "--quiet"],
                       check=True, capture_output=True)
        ref = meshio.read(vtu)
        m = warpmesh.mesh_shapes(spec, spacing=0.5, **kw)
        assert np.array_equal(ref.points[:, :2], m.points)
        assert np.array_equal(ref.cells_dict["triangle"], m.triangles)
        assert set(np.unique(m.regions)) == ({0, 1, 2, 3} if kw else {1, 2, 3})
        assert len(m.interfaces) > 0
    assert m.report["optimize"]["min_angle_after_deg"] > 30


def test_optimize_on_one_region_and_max_memory_everywhere(root):
    a = warpmesh.mesh_shape("flower:0,0,80,25,5", spacing=1, optimize=True)
    assert a.report["optimize"]["min_angle_after_deg"] > 35
    img = warpmesh.read_image(root / BRAIN, max_memory=64)
    assert warpmesh.mesh(img, labels="nonzero", spacing=2, optimize=True).report["optimize"]["min_angle_after_deg"] > 35
    for call in (lambda: warpmesh.mesh(img, materials="all", spacing=0.01, max_memory=16),
                 lambda: warpmesh.mesh(img, labels="nonzero", spacing=0.01, max_memory=16),
                 lambda: warpmesh.mesh_shape("circle:0,0,100", spacing=0.01, max_memory=16),
                 lambda: warpmesh.mesh_shapes("1=circle:0,0,100", spacing=0.01, max_memory=16)):
        with pytest.raises(warpmesh.InputError, match="max-memory|memory"):
            call()


def test_max_memory_bounds_the_call_not_the_callers_arrays(root):
    # Issue 50: max_memory counted the whole process, so after the caller
    # allocated a large array (2.2 GB in the report) a small sphere was
    # refused ("needs about 2240 MB").  Now it bounds what the call needs, its
    # stages above what the process held when it began.  Cheaply: a limit
    # below what this Python process holds already, once the array is made.
    big = np.ones(48 << 20 >> 3)  # 48 MB, touched
    import resource
    held_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    limit = 40
    assert held_mb > limit + 8  # the process alone is over the limit
    assert len(warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.25, max_memory=limit).tetrahedra) > 100
    assert len(warpmesh.mesh_shape("circle:0,0,10", max_memory=limit).triangles) > 100
    img = warpmesh.read_image(root / BRAIN)
    assert len(warpmesh.mesh(img, materials="all", spacing=2, max_memory=limit).interfaces) > 0
    labels = np.zeros((12, 12, 12), np.uint16)
    labels[2:10, 2:10, 2:10] = 1
    assert len(warpmesh.mesh3d(labels, labels="nonzero", max_memory=limit).tetrahedra) > 100
    # The limit still bounds the call, and its message adds up: the call's
    # need on top of what the call holds (its input), not the process's size.
    import re
    with pytest.raises(warpmesh.OptionError, match="max_memory") as e:
        warpmesh.mesh_shape("circle:0,0,100", spacing=0.01, max_memory=limit)
    held = re.search(r"on top of the (\d+) MB this call holds already", str(e.value))
    assert held and int(held.group(1)) < 16, str(e.value)
    del big
