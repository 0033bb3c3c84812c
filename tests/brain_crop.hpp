// brain_crop.hpp — the bundled 3D volume of the tests: a crop of the SPL
// brain atlas (tests/data/brain_crop22_labels.nrrd, read by the NRRD reader
// in millimetres), as the label-mode level set of one label (26 by default:
// the golden mesh's, with all-zero background tetrahedra and non-manifold
// boundary places at 1.5 mm).
#pragma once

#include <memory>
#include <string>

#include "warpmesh/levelset/levelset3.hpp"
#include "warpmesh/io/volume.hpp"

namespace warpmesh::testing {

inline std::unique_ptr<LevelSet3> brain_crop_levelset(int label = 26) {
    const Volume v = read_volume(std::string(WARPMESH_TEST_DATA) + "/brain_crop22_labels.nrrd");
    VolumeLevelSet3Options o;
    o.mode.mode = ImageMode::label;
    o.mode.labels = {label};
    return make_volume_levelset3(v, o);
}

}  // namespace warpmesh::testing
