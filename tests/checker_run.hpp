// checker_run.hpp — what the checker's tamper tests share: reading a
// certificate's lines, finding one, running warpmesh-check (or
// warpmesh-check-bcc) on an edited copy and expecting a rejection, splitting
// a line into fields.  (tests/CMakeLists.txt defines WARPMESH_CHECK_EXE.)
#pragma once
#include <boost/test/unit_test.hpp>

#include <sys/wait.h>
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

// The exit status from std::system's wait status (-1: no normal exit).
inline int exit_status(int rc) { return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1; }

// Index of the first line starting with `prefix` (a test failure if none).
inline std::size_t line_of(const std::vector<std::string>& lines, const std::string& prefix) {
    for (std::size_t i = 0; i < lines.size(); ++i)
        if (lines[i].rfind(prefix, 0) == 0) return i;
    BOOST_FAIL("no line " + prefix);
    return 0;
}

// The checker `exe` rejects `lines` (exit 1) with a message containing `why`.
inline void expect_rejected_by(const std::string& exe, const std::vector<std::string>& lines, const std::string& name,
                               const std::string& why) {
    std::string msg;
    BOOST_TEST(exit_status(run_checker(lines, name, &msg, exe)) == 1, name << ": " << msg);
    BOOST_TEST(msg.find(why) != std::string::npos, name << ": " << msg);
}

// The lines of proofs/NAME, at least `at_least` of them (a truncated or
// missing certificate fails the test here, not in a tamper case).
inline std::vector<std::string> proof_lines(const std::string& name, std::size_t at_least = 1) {
    auto l = read_lines(std::filesystem::path(WARPMESH_PROOFS_DIR) / name);
    BOOST_REQUIRE_GE(l.size(), at_least);
    return l;
}

#ifdef WARPMESH_CHECK_BCC_EXE
// warpmesh-check-bcc rejects `lines` (exit 1) with a message containing `why`.
inline void expect_bcc_rejected(const std::vector<std::string>& lines, const std::string& name, const std::string& why) {
    expect_rejected_by(WARPMESH_CHECK_BCC_EXE, lines, name, why);
}
#endif

// `lines` with the first line starting with `prefix` replaced by `line`.
inline std::vector<std::string> with_line(std::vector<std::string> lines, const std::string& prefix, const std::string& line) {
    lines[line_of(lines, prefix)] = line;
    return lines;
}

// Fields joined by single spaces (a line again).
inline std::string join_fields(const std::vector<std::string>& f) {
    std::string s;
    for (const auto& w : f) s += (s.empty() ? "" : " ") + w;
    return s;
}

// A line's whitespace-separated fields.
inline std::vector<std::string> fields(const std::string& line) {
    std::istringstream ss(line);
    std::vector<std::string> t;
    for (std::string w; ss >> w;) t.push_back(w);
    return t;
}

}  // namespace warpmesh::testing
