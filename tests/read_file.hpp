// read_file.hpp — the test suites' one helper for reading a whole file.
#pragma once

#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace warpmesh::testing {

// The bytes of a file; fails the test if it cannot be read.
inline std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    BOOST_REQUIRE_MESSAGE(in, "cannot read " << path.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace warpmesh::testing
