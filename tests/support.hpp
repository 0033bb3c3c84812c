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
#include "warpmesh/core/errors.hpp"

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

// The environment variable WARPMESH_TEST_SCALE: a number in (0, 1] (unset,
// empty or invalid: 1).  scripts/sanitize.sh sets 0.25, since under the
// sanitizers every case costs several times more; the Release run
// (scripts/test.sh) runs everything at scale 1.
inline double test_scale() {
    const char* env = std::getenv("WARPMESH_TEST_SCALE");
    if (!env || !*env) return 1;
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    return end && *end == '\0' && v > 0 && v <= 1 ? v : 1;
}

// How many cases a randomised test runs: n scaled by test_scale(), at least
// 1.  A test's "the trials exercised what they test" thresholds scale the
// same way.
inline int scaled(int n) { return std::max(1, static_cast<int>(n * test_scale() + 0.5)); }

// A test case decorator, *full_scale_only(): the case runs only at scale 1
// and is reported as skipped otherwise.  For cases whose cost is many runs of
// a whole program on large inputs (the checker on long certificate prefixes),
// which the Release run covers and the sanitizer run cannot afford.
inline boost::test_tools::assertion_result at_full_scale(boost::unit_test::test_unit_id) {
    boost::test_tools::assertion_result r(test_scale() == 1);
    if (!r) r.message() << "WARPMESH_TEST_SCALE < 1: left to the full-scale run";
    return r;
}
inline boost::unit_test::decorator::precondition full_scale_only() { return boost::unit_test::precondition(&at_full_scale); }

}  // namespace warpmesh::testing
