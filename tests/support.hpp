// support.hpp — what the Boost.Test suites share: a scratch directory, reading
// a whole file, matching an error's message, and the mesh measurements of
// mesh_math.hpp.
#pragma once

#include <boost/test/unit_test.hpp>

#include <stdlib.h>

#include <algorithm>
#include <cstdlib>

#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "mesh_math.hpp"
#include "warpmesh/errors.hpp"

namespace warpmesh::testing {

// A fresh directory under the system's temporary directory, removed with
// everything in it at the end (its permissions restored first, so a test may
// make it read-only).
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& prefix = "warpmesh") {
        std::string templ = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
        BOOST_REQUIRE(::mkdtemp(templ.data()) != nullptr);
        path = templ;
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::permissions(path, std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ec);
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
    std::size_t entries() const {
        return static_cast<std::size_t>(
            std::distance(std::filesystem::directory_iterator(path), std::filesystem::directory_iterator()));
    }
};

// The bytes of a file; fails the test if it cannot be read.
inline std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    BOOST_REQUIRE_MESSAGE(in, "cannot read " << path.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// True when f() throws an E whose message contains `needle`; otherwise false,
// with a test message saying what happened instead.
template <class E = InputError, class F>
bool throws_containing(F&& f, const std::string& needle) {
    try {
        f();
    } catch (const E& e) {
        const std::string msg = e.what();
        if (msg.find(needle) != std::string::npos) return true;
        BOOST_TEST_MESSAGE("exception without '" << needle << "': " << msg);
        return false;
    } catch (const std::exception& e) {
        BOOST_TEST_MESSAGE("wrong exception type: " << e.what());
        return false;
    }
    BOOST_TEST_MESSAGE("no exception (wanted '" << needle << "')");
    return false;
}
template <class F>
bool input_error_containing(F&& f, const std::string& needle) {
    return throws_containing<InputError>(std::forward<F>(f), needle);
}

// How many cases a randomised test runs: n scaled by the environment variable
// WARPMESH_TEST_SCALE (a number in (0, 1]; unset, empty or invalid: 1), at
// least 1.  scripts/sanitize.sh runs the suite with a quarter of the cases,
// since each costs several times more under the sanitizers; the Release run
// runs them all.  A test's "the trials exercised what they test" thresholds
// scale the same way.
inline int scaled(int n) {
    const char* env = std::getenv("WARPMESH_TEST_SCALE");
    double f = 1;
    if (env && *env) {
        char* end = nullptr;
        const double v = std::strtod(env, &end);
        if (end && *end == '\0' && v > 0 && v <= 1) f = v;
    }
    return std::max(1, static_cast<int>(n * f + 0.5));
}

}  // namespace warpmesh::testing
