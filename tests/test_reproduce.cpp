#define BOOST_TEST_MODULE reproduce
#include <boost/test/unit_test.hpp>

// scripts/reproduce-paper.sh --quick, run against the built binary
// (WARPMESH_EXE, so nothing is installed or built): the table has the promised
// columns, every mesh's angles lie within the bounds below, and the figures,
// meshes, reports and the sweep table are written.

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support.hpp"
#include "warpmesh/certify/certified.hpp"

using namespace warpmesh;

namespace fs = std::filesystem;

namespace {

// Every mesh's angles lie in its rule's certified theorem U (proofs/*.cert,
// compiled in); the table prints 4 decimals, hence the rounding slack.
constexpr double table_rounding = 5e-5;
DiagonalRule rule_named(const std::string& name) {
    BOOST_REQUIRE(name == "maxmin" || name == "separating");
    return name == "maxmin" ? DiagonalRule::maxmin : DiagonalRule::separating;
}

struct TempDir : warpmesh::testing::TempDir {
    TempDir() : warpmesh::testing::TempDir("warpmesh-reproduce") {}
};

std::string quoted(const std::string& s) {
    std::string r = "'";
    for (const char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return r + "'";
}

// Runs a shell command; returns its exit status (-1 if it did not exit).
int run(const std::string& cmd) {
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string script() { return std::string(WARPMESH_SOURCE_DIR) + "/scripts/reproduce-paper.sh"; }

std::string env() { return "WARPMESH_EXE=" + quoted(WARPMESH_EXE) + " "; }

// The cells of a Markdown table row "| a | b | … |", trimmed.
std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> r;
    std::stringstream ss(line);
    std::string cell;
    std::getline(ss, cell, '|');  // before the first bar
    while (std::getline(ss, cell, '|')) {
        const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
        r.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
    }
    if (!r.empty() && r.back().empty()) r.pop_back();  // after the last bar
    return r;
}

}  // namespace

BOOST_AUTO_TEST_CASE(quick_run_table_and_files) {
    TempDir dir;
    const fs::path out = dir.path / "results";
    const auto t0 = std::chrono::steady_clock::now();
    const int status = run(env() + "bash " + quoted(script()) + " --quick --out " + quoted(out.string()) + " > " +
                           quoted((dir.path / "log.txt").string()) + " 2>&1");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    {
        std::ifstream log(dir.path / "log.txt");
        std::stringstream ss;
        ss << log.rdbuf();
        BOOST_TEST_MESSAGE("reproduce-paper.sh --quick (" << seconds << " s):\n" << ss.str());
    }
    BOOST_REQUIRE_EQUAL(status, 0);
    BOOST_WARN_MESSAGE(seconds < 30, "--quick took " << seconds << " s, more than the promised 30 s");

    std::ifstream table(out / "table.md");
    BOOST_REQUIRE(table);
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(table, line);) {
        if (line.rfind("| case |", 0) == 0) header = cells(line);
        else if (!header.empty() && line.rfind("|---", 0) != 0 && line.rfind("| ", 0) == 0) rows.push_back(cells(line));
    }
    const std::vector<std::string> expected{"case",      "rule",      "lattice/spacing", "triangles",       "vertices",
                                            "min angle", "max angle", "time (s)",        "paper triangles", "paper time (s)"};
    BOOST_REQUIRE(header.size() >= expected.size());
    auto column = [&](const std::string& name) {
        for (std::size_t i = 0; i < header.size(); ++i)
            if (header[i] == name) return i;
        BOOST_FAIL("no column '" << name << "' in table.md");
        return std::size_t{0};
    };
    for (const auto& name : expected) column(name);

    BOOST_REQUIRE(!rows.empty());
    const std::size_t c_case = column("case"), c_min = column("min angle"), c_max = column("max angle"),
                      c_tri = column("triangles"), c_rule = column("rule");
    bool maxmin = false, separating = false;
    for (const auto& row : rows) {
        BOOST_REQUIRE_EQUAL(row.size(), header.size());
        const std::string& name = row[c_case];
        const double amin = std::stod(row[c_min]), amax = std::stod(row[c_max]);
        const CertifiedTheorem th = certified_theorem(rule_named(row[c_rule]));
        BOOST_TEST(amin >= th.min_deg_any - table_rounding, name << ": min angle " << amin);
        BOOST_TEST(amax <= th.max_deg_any + table_rounding, name << ": max angle " << amax);
        BOOST_TEST(std::stol(row[c_tri]) > 0);
        maxmin |= row[c_rule] == "maxmin";
        separating |= row[c_rule] == "separating";
        // Every row has its mesh, picture, histogram and report.
        BOOST_TEST(fs::file_size(out / "meshes" / (name + ".vtu")) > 0U);
        BOOST_TEST(fs::file_size(out / "figures" / (name + ".png")) > 0U);
        BOOST_TEST(fs::file_size(out / "figures" / (name + "-histogram.svg")) > 0U);
        BOOST_TEST(fs::file_size(out / "reports" / (name + ".json")) > 0U);
        // The PNG starts with the PNG signature.
        std::ifstream png(out / "figures" / (name + ".png"), std::ios::binary);
        char sig[8] = {};
        png.read(sig, 8);
        BOOST_TEST(std::string(sig + 1, 3) == "PNG");
    }
    BOOST_TEST(maxmin);
    BOOST_TEST(separating);

    // The sweep table: a header and at least one row per mesh kind.
    std::ifstream sweep(out / "sweep.md");
    BOOST_REQUIRE(sweep);
    int uniform = 0, graded = 0;
    for (std::string line; std::getline(sweep, line);) {
        if (line.find("| uniform |") != std::string::npos) ++uniform;
        if (line.find("| graded |") != std::string::npos) ++graded;
    }
    BOOST_TEST(uniform >= 1);
    BOOST_TEST(graded >= 1);
    // No scratch files left behind.
    for (const auto& e : fs::recursive_directory_iterator(out))
        BOOST_TEST(e.path().filename().string()[0] != '.', e.path());
}

BOOST_AUTO_TEST_CASE(bad_arguments_are_refused) {
    TempDir dir;
    BOOST_TEST(run(env() + "bash " + quoted(script()) + " --no-such-option > /dev/null 2>&1") == 2);
    BOOST_TEST(run(env() + "bash " + quoted(script()) + " --quick --out > /dev/null 2>&1") == 2);
    BOOST_TEST(run("WARPMESH_EXE=" + quoted((dir.path / "missing").string()) + " bash " + quoted(script()) +
                   " --quick --out " + quoted((dir.path / "r").string()) + " > /dev/null 2>&1") == 1);
}
