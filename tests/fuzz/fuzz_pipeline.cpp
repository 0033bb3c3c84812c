// fuzz_pipeline.cpp — libFuzzer target for the whole meshing pipeline.
//
// Decodes a tiny image and the meshing options from the input (layout in
// fuzz_checks.hpp: size 2..24 per side, spacing, threshold or label mode,
// diagonal rule, uniform or graded, grading, max size, and in label mode
// every label as a material with per-material caps), meshes it and checks the mesh
// invariants: check_mesh, every triangle of a warped square inside its key's
// certified interval and every angle inside the rule's certified theorem U, tags, vertices inside the lattice, and for graded meshes
// the same area and boundary as the uniform mesh, a valid quadtree and the
// size bounds (multi-material: the uniform interfaces, every material's cap).  A
// violation aborts, so the fuzzer reports it.  Built by scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    warpmesh::fuzz::check_pipeline(std::span<const std::uint8_t>(data, size));
    return 0;
}
