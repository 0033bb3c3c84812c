// fuzz_image_reader.cpp — libFuzzer target for the image readers.
//
// Feeds arbitrary bytes to decode_image (PGM P2/P5, PNG through libpng) with
// a small pixel limit, so that no input can make it allocate much.  Every
// input must either decode into a consistent Image or throw InputError;
// anything else (a crash, a sanitizer report, another exception, an image
// that breaks the documented invariants) aborts and the fuzzer reports it.
//
// Built by scripts/fuzz.sh (clang -fsanitize=fuzzer,address,undefined).  The
// checks live in fuzz_checks.hpp so that tests/test_degenerate.cpp can replay
// the seed corpus and every file in regressions/image_reader/ through exactly
// the same code in the normal (and the sanitizer) test build.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    warpmesh::fuzz::check_image_reader(std::span<const std::uint8_t>(data, size));
    return 0;
}
