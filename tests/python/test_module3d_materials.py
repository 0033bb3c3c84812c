"""warpmesh.mesh3d with several materials (issue 47): materials= of a label
volume (a numpy array or a file path) and shapes= of analytic materials give
the command line's mesh, with a region tag per tetrahedron, the interfaces
between materials and their region pairs, the region names and the report's
per-material figures; bad arguments raise InputError naming the keyword."""
import json
import pathlib
import subprocess
import warnings

import numpy as np
import pytest

import warpmesh
from conftest import executable, require, write_nrrd

NESTED = "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"


def labels_zyx():
    z, y, x = np.mgrid[0:20, 0:20, 0:28]
    a = np.zeros(x.shape, np.uint8)
    a[2:18, 2:18, 2:14] = 3
    a[(x - 8) ** 2 + (y - 10) ** 2 + (z - 10) ** 2 < 16] = 5
    a[4:16, 4:16, 14:26] = 7
    return a


def faces_of(tets):
    """Each tetrahedron's four faces as sorted vertex triples."""
    return {tuple(sorted(f)) for t in tets.tolist() for f in (t[1:], t[:1] + t[2:], t[:2] + t[3:], t[:3])}


def test_materials_of_an_array_and_a_path_give_the_cli_mesh(tmp_path):
    meshio = require("meshio", "python3-meshio")
    write_nrrd(tmp_path / "l.nrrd", labels_zyx(), (0.5, 0.5, 0.5))
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "l.nrrd", "--materials", "all", "-o", "l.vtu", "--report",
                    "l.json", "--quiet"], cwd=tmp_path, check=True, timeout=120)
    ref = meshio.read(tmp_path / "l.vtu")
    report = json.loads((tmp_path / "l.json").read_text())
    for m in (warpmesh.mesh3d(labels_zyx(), materials="all", voxel_size=0.5),
              warpmesh.mesh3d(pathlib.Path(tmp_path / "l.nrrd"), materials="all"),
              warpmesh.mesh3d(labels_zyx(), materials=[3, 5, 7], voxel_size=0.5)):
        assert np.allclose(m.points, ref.points, rtol=1e-14, atol=1e-12)
        assert np.array_equal(m.tetrahedra, ref.cells_dict["tetra"])
        assert np.array_equal(m.regions, ref.cell_data["region"][0])
        assert m.region_names == {3: "label_3", 5: "label_5", 7: "label_7"}
        assert m.report["materials"] == report["materials"]
        assert len(m.interfaces) == report["interface_faces"] > 0
    # Every interface face is a face of a tetrahedron of each of its two regions.
    for a, b in {tuple(sorted(p)) for p in m.interface_regions.tolist()}:
        sel = [k for k, p in enumerate(m.interface_regions.tolist()) if sorted(p) == [a, b]]
        faces = {tuple(sorted(f)) for f in m.interfaces[sel].tolist()}
        assert faces <= faces_of(m.tetrahedra[m.regions == a]) and faces <= faces_of(m.tetrahedra[m.regions == b])
    assert {tuple(sorted(p)) for p in m.interface_regions.tolist()} == {(3, 5), (3, 7)}


def test_shapes_give_the_cli_mesh_with_interfaces(tmp_path):
    meshio = require("meshio", "python3-meshio")
    subprocess.run([executable("WARPMESH_EXE"), "mesh3d", "--shapes", NESTED, "--spacing", "0.2", "--background",
                    "keep", "-o", "s.vtu", "--quiet"], cwd=tmp_path, check=True, timeout=120)
    ref = meshio.read(tmp_path / "s.vtu")
    m = warpmesh.mesh3d(shapes=NESTED, spacing=0.2, background="keep")
    assert np.array_equal(m.tetrahedra, ref.cells_dict["tetra"]) and np.array_equal(m.regions, ref.cell_data["region"][0])
    assert m.region_names == {0: "background", 1: "material_1", 2: "material_2"}
    assert [x["tag"] for x in m.report["materials"]] == [0, 1, 2]
    assert m.interfaces.shape == (m.report["interface_faces"], 3) and m.interface_regions.shape[1] == 2
    assert {tuple(sorted(p)) for p in m.interface_regions.tolist()} == {(0, 1), (1, 2)}
    # Each interface face's normal points from its first region into the second.
    p = m.points
    a, b, c = (p[m.interfaces[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    centre = (a + b + c) / 3
    inner = np.all(m.interface_regions == [2, 1], axis=1)
    assert inner.any() and (np.einsum("ij,ij->i", n[inner], centre[inner]) > 0).all()  # out of the inner sphere
    one = warpmesh.mesh3d(shapes=NESTED, spacing=0.2)
    assert set(np.unique(one.regions).tolist()) == {1, 2} and one.report["face_rule"] == "parity"


def test_junctions_are_certified_and_verified():
    """Where three or four materials meet, the tetrahedra are certified by
    proofs/bcc_junctions.cert (the build has it) and checked with verify."""
    spec = "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = warpmesh.mesh3d(shapes=spec, spacing=0.1, verify=True)
    j = m.report["junctions"]
    assert j["tetrahedra"] > 0 and j["certified"] is True and j["certificate"] == "proofs/bcc_junctions.cert"
    c = m.report["certified"]
    assert c["uncertified_tetrahedra"] == 0 and c["certified_tetrahedra"] == len(m.tetrahedra) and c["verified"]
    assert c["min_dihedral_deg"] <= m.report["min_dihedral_deg"] and m.report["max_dihedral_deg"] <= c["max_dihedral_deg"]
    assert not any("junction" in str(w.message) for w in caught)


@pytest.mark.parametrize("call, message", [
    (lambda: warpmesh.mesh3d("sphere:0,0,0,1", spacing=0.3, materials="all"), "materials apply to volumes"),
    (lambda: warpmesh.mesh3d(labels_zyx(), shapes=NESTED, spacing=0.3), "give a volume or shapes=, not both"),
    (lambda: warpmesh.mesh3d(shapes=3, spacing=0.3), "shapes must be a string"),
    (lambda: warpmesh.mesh3d(shapes=NESTED), "spacing is required"),
    (lambda: warpmesh.mesh3d(), "give a volume"),
    (lambda: warpmesh.mesh3d(labels_zyx(), label=3, background="keep"), "background='keep' applies to several materials"),
    (lambda: warpmesh.mesh3d(labels_zyx(), materials="all", label=3), "materials (every label its own region) excludes"),
    (lambda: warpmesh.mesh3d(labels_zyx(), materials="all", face_rule="delaunay"),
     "face_rule='delaunay' is not available with several materials"),
    (lambda: warpmesh.mesh3d(labels_zyx(), materials="3,x"), "materials expects all or a label list"),
    (lambda: warpmesh.mesh3d(labels_zyx(), materials="3,4"), "not present in the volume: 4"),
    (lambda: warpmesh.mesh3d(shapes=NESTED, spacing=0.3, background="maybe"), "background expects 'drop' or 'keep'"),
    (lambda: warpmesh.mesh3d(lambda x, y, z: x, box=(0, 0, 0, 1, 1, 1), spacing=0.3, materials="all"),
     "materials apply to volumes"),
])
def test_bad_arguments_raise_input_error(call, message):
    with pytest.raises(warpmesh.InputError) as e:
        call()
    assert message in str(e.value), str(e.value)
    assert "--" not in str(e.value)
