// fuzz_nrrd_reader.cpp — libFuzzer target for the NRRD reader (decode_nrrd).
// The checks live in fuzz_volume_checks.hpp, replayed on the seeds and
// regressions by tests/test_volume_io.cpp.  Built and run by scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_volume_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    warpmesh::fuzz::check_nrrd_reader(std::span<const std::uint8_t>(data, size));
    return 0;
}
