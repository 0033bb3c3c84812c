// checker_run.hpp — what the checker's tamper tests share: reading a
// certificate's lines, running warpmesh-check on an edited copy, splitting a
// line into fields.  (tests/CMakeLists.txt defines WARPMESH_CHECK_EXE.)
#pragma once
#include <boost/test/unit_test.hpp>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support.hpp"  // full_scale_only

#ifndef WARPMESH_CHECK_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_EXE"
#endif

namespace warpmesh::testing {

inline std::vector<std::string> read_lines(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// Writes `lines` as <tmp>/<name>.cert, runs warpmesh-check (or the checker
// `exe`) on it and returns its exit status; its stderr goes to *message (and
// the test log).
inline int run_checker(const std::vector<std::string>& lines, const std::string& name, std::string* message = nullptr,
                       const std::string& exe = WARPMESH_CHECK_EXE) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_tamper_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path f = dir / (name + ".cert");
    {
        std::ofstream out(f);
        for (const auto& l : lines) out << l << "\n";
    }
    const std::string cmd = "\"" + exe + "\" \"" + f.string() + "\" >/dev/null 2>" +
                            (dir / (name + ".err")).string();
    const int rc = std::system(cmd.c_str());
    std::ifstream err(dir / (name + ".err"));
    std::stringstream ss;
    ss << err.rdbuf();
    BOOST_TEST_MESSAGE(name << ": " << ss.str());
    if (message) *message = ss.str();
    fs::remove_all(dir);
    return rc;
}

// A line's whitespace-separated fields.
inline std::vector<std::string> fields(const std::string& line) {
    std::istringstream ss(line);
    std::vector<std::string> t;
    for (std::string w; ss >> w;) t.push_back(w);
    return t;
}

}  // namespace warpmesh::testing
