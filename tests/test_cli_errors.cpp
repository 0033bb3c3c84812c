// End-to-end tests of the command line on hostile and broken inputs: every
// refusal must exit with the documented status (1 bad input or output, 2
// usage), print a message on stderr that names the problem, and leave nothing
// behind in the output directory — no mesh, no report, no temporary file.
//
// The binary (WARPMESH_EXE) is run through /bin/sh with stdout and stderr
// redirected to files outside the output directory.  Inputs are written into
// their own directory, so that the output directory's listing (dotfiles
// included) can be compared before and after.
#define BOOST_TEST_MODULE cli_errors
#include <boost/test/unit_test.hpp>

#include "support.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

using warpmesh::testing::slurp;

void write_bytes(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    BOOST_REQUIRE(out.good());
}

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

struct Result {
    int code = -1;
    std::string out, err;
};

// A scratch area: in/ (inputs), out/ (the working and output directory), and
// the captured streams beside them.
struct Sandbox {
    fs::path root, in, out;

    Sandbox() {
        std::string templ = (fs::temp_directory_path() / "warpmesh-cli-XXXXXX").string();
        BOOST_REQUIRE(::mkdtemp(templ.data()) != nullptr);
        root = templ;
        in = root / "in";
        out = root / "out";
        fs::create_directories(in);
        fs::create_directories(out);
    }
    ~Sandbox() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }

    fs::path input(const std::string& name, const std::string& bytes) const {
        write_bytes(in / name, bytes);
        return in / name;
    }

    // Runs `prefix warpmesh ARGS` in out/ (prefix: shell commands such as
    // "ulimit -f 2;").
    Result run(const std::vector<std::string>& args, const std::string& prefix = "") const {
        // Appended piece by piece: g++ 12 -O3 warns (-Wrestrict, a known false
        // positive) on `" " + std::string&&`.
        std::string cmd = "cd " + quote(out.string()) + " && " + prefix + " " + quote(WARPMESH_EXE);
        for (const auto& a : args) cmd.append(" ").append(quote(a));
        cmd.append(" >").append(quote((root / "stdout").string()));
        cmd.append(" 2>").append(quote((root / "stderr").string()));
        const int status = std::system(("/bin/sh -c " + quote(cmd)).c_str());
        Result r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
        r.out = slurp(root / "stdout");
        r.err = slurp(root / "stderr");
        return r;
    }

    // Runs and checks: exit `code`, stderr contains every one of `needles`
    // (case-sensitive), and out/ is exactly as it was before.
    Result refuse(const std::vector<std::string>& args, int code, std::initializer_list<std::string> needles,
                  const std::string& prefix = "") const {
        const auto before = listing(out);
        const Result r = run(args, prefix);
        std::string line;
        for (const auto& a : args) line += " " + a;
        BOOST_TEST_INFO("warpmesh" << line << "\nstderr: " << r.err);
        BOOST_TEST(r.code == code);
        for (const auto& n : needles) {
            BOOST_TEST_INFO("warpmesh" << line << "\nstderr: " << r.err << "\nexpected to contain: " << n);
            BOOST_TEST(r.err.find(n) != std::string::npos);
        }
        BOOST_TEST_INFO("warpmesh" << line);
        BOOST_TEST(r.err.find("warpmesh: internal error") == std::string::npos);
        const auto after = listing(out);
        std::string extra;
        for (const auto& f : after)
            if (!before.count(f)) extra += " " + f;
        BOOST_TEST_INFO("warpmesh" << line << "\nleft in the output directory:" << extra);
        BOOST_TEST(extra.empty());
        return r;
    }
};

// --- input builders -----------------------------------------------------------

std::string pgm_p5(int w, int h, int maxval, const std::vector<int>& px) {
    std::string s = "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n" + std::to_string(maxval) + "\n";
    for (int v : px) {
        if (maxval > 255) s += static_cast<char>(v >> 8);
        s += static_cast<char>(v & 255);
    }
    return s;
}

// A w x h 8-bit image: a bright disc in the middle on black.
std::string disc_pgm(int w, int h) {
    std::vector<int> px;
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const double dx = c - (w - 1) / 2.0, dy = r - (h - 1) / 2.0;
            px.push_back(dx * dx + dy * dy <= 0.1 * w * h ? 255 : 0);
        }
    return pgm_p5(w, h, 255, px);
}

std::uint32_t crc32(const std::string& s) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : s) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

std::string be32(std::uint32_t v) {
    return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
}

std::string png_chunk(const std::string& type, const std::string& data, bool bad_crc = false) {
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32(type + data) ^ (bad_crc ? 1u : 0u));
}

// zlib stream of `raw` in stored (uncompressed) deflate blocks.
std::string zlib_stored(const std::string& raw) {
    std::string z = "\x78\x01";
    std::size_t pos = 0;
    do {
        const std::size_t n = std::min<std::size_t>(raw.size() - pos, 65535);
        const bool last = pos + n == raw.size();
        z += static_cast<char>(last ? 1 : 0);
        z += static_cast<char>(n & 255), z += static_cast<char>(n >> 8);
        z += static_cast<char>(~n & 255), z += static_cast<char>((~n >> 8) & 255);
        z += raw.substr(pos, n);
        pos += n;
    } while (pos < raw.size());
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    return z + be32(b << 16 | a);
}

std::string png_ihdr(std::uint32_t w, std::uint32_t h, int depth, int color_type, bool bad_crc = false) {
    std::string d = be32(w) + be32(h);
    d += static_cast<char>(depth), d += static_cast<char>(color_type);
    d += std::string(3, '\0');  // compression, filter, interlace
    return png_chunk("IHDR", d, bad_crc);
}

const std::string png_signature("\x89PNG\r\n\x1a\n", 8);

// A valid 8-bit gray PNG (filter type 0 on every row).
std::string png_gray8(int w, int h, unsigned char value = 200) {
    std::string raw;
    for (int r = 0; r < h; ++r) raw += '\0' + std::string(static_cast<std::size_t>(w), static_cast<char>(value));
    return png_signature + png_ihdr(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), 8, 0) +
           png_chunk("IDAT", zlib_stored(raw)) + png_chunk("IEND", "");
}

}  // namespace

// --- the harness itself -----------------------------------------------------------

BOOST_AUTO_TEST_CASE(a_good_run_writes_exactly_the_requested_files) {
    Sandbox sb;
    const auto img = sb.input("disc.pgm", disc_pgm(16, 12));
    const Result r = sb.run({"mesh", img.string(), "-o", "m.vtu", "--report", "r.json", "--quiet"});
    BOOST_TEST_INFO(r.err);
    BOOST_TEST(r.code == 0);
    BOOST_TEST((listing(sb.out) == std::set<std::string>{"m.vtu", "r.json"}));
}

// The graded report carries the uniform report's counts of the warped squares
// and of the squares where the separating rule overrode max-min, and they
// agree: the graded mesh's warped squares are the uniform mesh's (src/mesh2d/graded/quadtree.hpp).
BOOST_AUTO_TEST_CASE(graded_and_uniform_reports_count_the_same_warped_squares) {
    Sandbox sb;
    const auto img = sb.input("disc.pgm", disc_pgm(40, 32)).string();
    auto count = [&](const std::string& json, const std::string& key) -> long {
        const std::string k = "\"" + key + "\": ";
        const auto at = json.find(k);
        BOOST_TEST_INFO("report: " << json);
        BOOST_REQUIRE(at != std::string::npos);
        return std::stol(json.substr(at + k.size()));
    };
    for (const std::string rule : {"separating", "maxmin"}) {
        const Result u = sb.run({"mesh", img, "--spacing", "0.25", "--diagonal", rule, "--report", "u.json", "--quiet"});
        const Result g = sb.run({"mesh", img, "--spacing", "0.25", "--diagonal", rule, "--graded", "--report", "g.json", "--quiet"});
        BOOST_TEST_INFO(u.err << g.err);
        BOOST_REQUIRE(u.code == 0 && g.code == 0);
        const std::string uj = slurp(sb.out / "u.json"), gj = slurp(sb.out / "g.json");
        BOOST_TEST(count(gj, "warped_squares") > 0);
        BOOST_TEST(count(gj, "warped_squares") == count(uj, "warped_squares"));
        BOOST_TEST(count(gj, "separating_overrides") == count(uj, "separating_overrides"));
        BOOST_TEST(count(gj, "warped_points") == count(uj, "warped_points"));
    }
}

// --- usage errors: exit 2 ---------------------------------------------------------

BOOST_AUTO_TEST_CASE(usage_errors_exit_2) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(8, 8)).string();
    sb.refuse({}, 2, {"usage"});
    sb.refuse({"frobnicate"}, 2, {"unknown command 'frobnicate'"});
    sb.refuse({"mesh", img, "-o", "m.vtu", "--frob"}, 2, {"unknown option '--frob'"});
    sb.refuse({"mesh", img, "-o"}, 2, {"-o needs a value"});
    sb.refuse({"mesh", "-o", "m.vtu"}, 2, {"exactly one of an input image or --shape"});
    sb.refuse({"mesh", img, "--shape", "circle:0,0,1", "-o", "m.vtu"}, 2, {"exactly one"});
    sb.refuse({"mesh", img, img, "-o", "m.vtu"}, 2, {"more than one input"});
    sb.refuse({"mesh", img, "--quiet"}, 2, {"nothing to do"});
    sb.refuse({"mesh", img, "--iso", "3", "--label", "1", "-o", "m.vtu"}, 2, {"exclude each other"});
    sb.refuse({"mesh", "--shape", "circle:0,0,1", "--iso", "3", "-o", "m.vtu"}, 2, {"apply to images"});
    sb.refuse({"mesh", img, "--inside", "sideways", "-o", "m.vtu"}, 2, {"--inside", "sideways"});
    sb.refuse({"mesh", img, "--diagonal", "best", "-o", "m.vtu"}, 2, {"--diagonal", "best"});
    sb.refuse({"mesh", img, "--iso", "nan", "-o", "m.vtu"}, 2, {"--iso expects a finite number"});
    sb.refuse({"mesh", img, "--iso", "inf", "-o", "m.vtu"}, 2, {"--iso expects a finite number"});
    sb.refuse({"mesh", img, "--max-cell", "3", "--graded", "-o", "m.vtu"}, 2, {"power of two"});
    sb.refuse({"mesh", img, "--grading", "3", "--graded", "-o", "m.vtu"}, 2, {"--grading must be between 1.1 and 2"});
    sb.refuse({"mesh", img, "--grading", "1", "--graded", "-o", "m.vtu"}, 2, {"--grading must be between 1.1 and 2"});
    sb.refuse({"mesh", img, "--grading", "nan", "--graded", "-o", "m.vtu"}, 2, {"--grading"});
    sb.refuse({"mesh", img, "--max-size", "-1", "--graded", "-o", "m.vtu"}, 2, {"--max-size must be positive"});
    sb.refuse({"mesh", img, "--max-size", "2", "--graded", "-o", "m.vtu"}, 2, {"below sqrt(5) * spacing = 2.23607", "--spacing 0.894427 or less"});
    sb.refuse({"mesh", img, "--max-size", "4", "--spacing", "2", "-o", "m.vtu"}, 2, {"below sqrt(5) * spacing"});
    sb.refuse({"mesh", img, "--max-pixels", "0", "-o", "m.vtu"}, 2, {"--max-pixels"});
    sb.refuse({"mesh", img, "--max-squares", "-5", "-o", "m.vtu"}, 2, {"--max-squares"});
    sb.refuse({"mesh", img, "--threads", "0", "-o", "m.vtu"}, 2, {"--threads"});
    sb.refuse({"mesh", img, "--repeat", "0", "-o", "m.vtu"}, 2, {"--repeat expects 1 to 1000"});
    sb.refuse({"mesh", img, "--repeat", "two", "-o", "m.vtu"}, 2, {"--repeat expects an integer"});
    sb.refuse({"mesh", img, "--msh-version", "4", "-o", "m.msh"}, 2, {"--msh-version expects '4.1' or '2.2', got '4'"});
    // The 3D face rule: a word of two, and 3D only.
    for (const char* bad : {"Delaunay", "shorter", ""})
        sb.refuse({"mesh3d", "--shape", "sphere:0,0,0,1", "--spacing", "0.3", "--face-rule", bad, "-o", "m.vtu"}, 2,
                  {"--face-rule expects 'parity' or 'delaunay', got '" + std::string(bad) + "'"});
    sb.refuse({"mesh3d", "--shape", "sphere:0,0,0,1", "--spacing", "0.3", "-o", "m.vtu", "--face-rule"}, 2, {"--face-rule needs a value"});
    sb.refuse({"mesh", img, "--face-rule", "delaunay", "-o", "m.vtu"}, 2, {"--face-rule applies to 3D meshes (warpmesh mesh3d)"});
}

// Issue 27 item 6: options that did nothing were accepted silently —
// --max-size 0 gave the unbounded mesh (while -1 was refused), --max-cell 0
// the default cells, and --grading / --max-cell without --graded,
// --min-spacing without --guarantee flat, --inside in label or materials
// mode and --units with a shape were ignored.  Each is now a usage error
// (exit 2, nothing written) saying what to do; the same options where they
// apply are accepted.
BOOST_AUTO_TEST_CASE(options_without_effect_are_refused_not_ignored) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(32, 32)).string();
    sb.refuse({"mesh", img, "--max-size", "0", "-o", "m.vtu"}, 2, {"--max-size must be positive", "leave it out for no size bound"});
    sb.refuse({"mesh", img, "--max-size", "0", "--graded", "-o", "m.vtu"}, 2, {"--max-size must be positive"});
    sb.refuse({"mesh", img, "--max-size", "-1", "-o", "m.vtu"}, 2, {"--max-size must be positive"});
    sb.refuse({"mesh", img, "--max-cell", "0", "--graded", "-o", "m.vtu"}, 2,
              {"--max-cell must be a power of two >= 1", "leave it out"});
    sb.refuse({"mesh", img, "--max-cell", "-4", "--graded", "-o", "m.vtu"}, 2, {"--max-cell must be a power of two"});
    for (const char* g : {"1.5", "2"})
        sb.refuse({"mesh", img, "--grading", g, "-o", "m.vtu"}, 2, {"--grading applies to graded meshes: add --graded"});
    sb.refuse({"mesh", img, "--max-cell", "4", "-o", "m.vtu"}, 2, {"--max-cell applies to graded meshes: add --graded"});
    sb.refuse({"mesh", img, "--min-spacing", "0.5", "-o", "m.vtu"}, 2, {"--min-spacing applies to --guarantee flat"});
    sb.refuse({"mesh", img, "--label", "255", "--inside", "below", "-o", "m.vtu"}, 2, {"--inside applies to threshold mode"});
    sb.refuse({"mesh", img, "--materials", "all", "--inside", "below", "-o", "m.vtu"}, 2, {"--materials", "--inside"});
    sb.refuse({"mesh", "--shape", "circle:0,0,3", "--units", "mm", "-o", "m.vtu"}, 2, {"--units", "not to --shape"});
    sb.refuse({"mesh", "--shapes", "1=circle:0,0,3", "--units", "pixels", "-o", "m.vtu"}, 2, {"--units", "not to --shape"});
    sb.refuse({"mesh", "--shapes", "1=circle:0,0,3", "--inside", "below", "-o", "m.vtu"}, 2, {"apply to images"});
    // --units mm on an image without a physical pixel size was meshed in pixels.
    sb.refuse({"mesh", img, "--units", "mm", "-o", "m.vtu"}, 1, {"--units mm", "PGM", "no physical pixel size", "--pixel-size"});
    for (const std::vector<std::string>& ok :
         {std::vector<std::string>{"--graded", "--max-cell", "4", "--grading", "1.5", "--max-size", "8"},
          std::vector<std::string>{"--guarantee", "flat", "--min-spacing", "0.5"},
          std::vector<std::string>{"--iso", "100", "--inside", "below"},
          std::vector<std::string>{"--units", "mm", "--pixel-size", "0.5"}}) {
        std::vector<std::string> args{"mesh", img, "-o", "m.vtu", "--quiet"};
        args.insert(args.end(), ok.begin(), ok.end());
        const Result r = sb.run(args);
        BOOST_TEST(r.code == 0, r.err);
        fs::remove(sb.out / "m.vtu");
    }
}

// Issue 27 item 4: a CSG shape with an empty part (an intersection of shapes
// whose bounding boxes are disjoint) was refused as "bounding boxes are
// disjoint" though it is the rest of the shape; only an empty whole is
// refused, as "the region is empty".
BOOST_AUTO_TEST_CASE(csg_with_an_empty_part_is_meshed_only_an_empty_whole_refused) {
    Sandbox sb;
    const std::string empty = "intersect(circle:20,0,1;circle:-20,0,1)";
    for (const std::string& shape : {"union(circle:0,0,5;" + empty + ")", "diff(circle:0,0,5;" + empty + ")"}) {
        const Result r = sb.run({"mesh", "--shape", shape, "-o", "m.vtu", "--quiet"});
        BOOST_TEST(r.code == 0, shape << ": " << r.err);
        BOOST_TEST(fs::exists(sb.out / "m.vtu"));
        fs::remove(sb.out / "m.vtu");
    }
    sb.refuse({"mesh", "--shape", "intersect(circle:0,0,5;" + empty + ")", "-o", "m.vtu"}, 1,
              {"the region is empty", empty + " is empty", "bounding boxes of its shapes are disjoint"});
    sb.refuse({"mesh", "--shapes", "1=circle:0,0,5;2=" + empty, "-o", "m.vtu"}, 1, {"the region is empty"});
}

// --max-size-of T=H (per-material maximum sizes): refused with a message naming
// the problem, before anything is written.  With a uniform mesh it is only
// checked, as --max-size is (every triangle is within the lattice spacing).
BOOST_AUTO_TEST_CASE(max_size_of_refusals) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(16, 12)).string();  // labels 0 and 255
    const std::string shapes = "1=circle:0,0,4;2=circle:3,0,3";
    sb.refuse({"mesh", img, "--max-size-of", "255=4", "--graded", "-o", "m.vtu"}, 2,
              {"--max-size-of applies to --materials and --shapes", "use --max-size"});
    sb.refuse({"mesh", "--shape", "circle:0,0,4", "--max-size-of", "1=4", "-o", "m.vtu"}, 2, {"--max-size-of applies to --materials"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "255", "-o", "m.vtu"}, 2, {"--max-size-of expects T=H", "'255'"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "x=4", "-o", "m.vtu"}, 2, {"--max-size-of T expects an integer, got 'x'"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "255=abc", "-o", "m.vtu"}, 2,
              {"--max-size-of H expects a finite number, got 'abc'"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "255=nan", "-o", "m.vtu"}, 2, {"--max-size-of H expects a finite number"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "-3=4", "-o", "m.vtu"}, 2, {"T must be a label or tag 0..65535"});
    for (const char* h : {"0", "-1"})
        sb.refuse({"mesh", img, "--materials", "all", "--graded", "--max-size-of", std::string("255=") + h, "-o", "m.vtu"}, 2,
                  {"--max-size-of 255=H: H must be positive and finite"});
    sb.refuse({"mesh", img, "--materials", "all", "--graded", "--max-size-of", "255=2", "-o", "m.vtu"}, 2,
              {"--max-size-of 255=H: H 2 is below sqrt(5) * spacing = 2.23607", "--spacing 0.894427 or less"});
    sb.refuse({"mesh", img, "--materials", "all", "--max-size-of", "255=4", "--spacing", "2", "-o", "m.vtu"}, 2,
              {"below sqrt(5) * spacing"});  // uniform: checked all the same
    sb.refuse({"mesh", img, "--materials", "all", "--graded", "--max-size-of", "255=4", "--max-size-of", "255=8", "-o", "m.vtu"}, 2,
              {"--max-size-of: material 255 is given twice"});
    sb.refuse({"mesh", img, "--materials", "all", "--graded", "--max-size-of", "7=4", "-o", "m.vtu"}, 1,
              {"--max-size-of 7=H: no material has tag 7 (the materials: 255)"});
    sb.refuse({"mesh", "--shapes", shapes, "--graded", "--max-size-of", "3=4", "-o", "m.vtu"}, 1,
              {"no material has tag 3 (the materials: 1, 2)"});
    sb.refuse({"mesh", "--shapes", shapes, "--graded", "--max-size-of", "0=4", "-o", "m.vtu"}, 1,
              {"the background (tag 0) is not output", "--background keep"});
    // Accepted: the background kept and capped; a uniform mesh (checked only).
    for (const std::vector<std::string>& ok : {std::vector<std::string>{"--graded", "--background", "keep", "--max-size-of", "0=4"},
                                               std::vector<std::string>{"--max-size-of", "1=4"}}) {
        std::vector<std::string> args{"mesh", "--shapes", shapes, "-o", "m.vtu", "--quiet"};
        args.insert(args.end(), ok.begin(), ok.end());
        const Result r = sb.run(args);
        BOOST_TEST_INFO(r.err);
        BOOST_TEST(r.code == 0);
    }
}

// --repeat (benchmarks) meshes several times in one process: the files are
// those of a single run, byte for byte, and the report says it was repeated.
BOOST_AUTO_TEST_CASE(repeat_writes_the_mesh_of_one_run) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(24, 20)).string();
    for (const bool graded : {false, true}) {
        std::vector<std::string> once{"mesh", img, "--spacing", "0.5", "-o", "a.msh", "--report", "a.json", "--quiet"};
        std::vector<std::string> thrice{"mesh", img, "--spacing", "0.5", "-o", "b.msh", "--report", "b.json", "--quiet", "--repeat", "3"};
        if (graded) once.push_back("--graded"), thrice.push_back("--graded");
        const Result r1 = sb.run(once), r3 = sb.run(thrice);
        BOOST_TEST_INFO(r1.err << r3.err);
        BOOST_REQUIRE(r1.code == 0 && r3.code == 0);
        BOOST_TEST(slurp(sb.out / "a.msh") == slurp(sb.out / "b.msh"));
        BOOST_TEST(slurp(sb.out / "b.json").find("\"repeat\": 3") != std::string::npos);
        BOOST_TEST(slurp(sb.out / "a.json").find("\"repeat\"") == std::string::npos);
    }
}

// --- spacing ------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(non_positive_and_absurd_spacing) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(8, 8)).string();
    for (const char* s : {"0", "-1", "-0", "1e300", "1e10"})
        sb.refuse({"mesh", img, "--spacing", s, "-o", "m.vtu"}, 2, {"--spacing must be positive"});
    for (const char* s : {"nan", "inf", "-inf", "abc", "1.5x", ""})
        sb.refuse({"mesh", img, "--spacing", s, "-o", "m.vtu"}, 2, {"--spacing expects a finite number"});
    // Tiny spacings would make a huge lattice: refused by --max-squares before
    // anything is allocated (a 1e-300 lattice would not even be countable).
    for (const char* s : {"1e-6", "1e-300", "4.9e-324"}) {
        sb.refuse({"mesh", img, "--spacing", s, "-o", "m.vtu"}, 1, {"--max-squares"});
        sb.refuse({"mesh", "--shape", "circle:0,0,10", "--spacing", s, "-o", "m.vtu"}, 1, {"--max-squares"});
    }
}

BOOST_AUTO_TEST_CASE(max_squares_and_max_pixels_limits) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(16, 16)).string();
    // 15 x 15 squares at spacing 1.
    sb.refuse({"mesh", img, "--max-squares", "224", "-o", "m.vtu"}, 1, {"more than --max-squares 224"});
    BOOST_TEST(sb.run({"mesh", img, "--max-squares", "225", "-o", "m.vtu", "--quiet"}).code == 0);
    fs::remove(sb.out / "m.vtu");
    sb.refuse({"mesh", img, "--spacing", "0.1", "--max-squares", "20000", "-o", "m.vtu"}, 1, {"--max-squares 20000"});
    sb.refuse({"mesh", "--shape", "circle:0,0,10", "--max-squares", "100", "-o", "m.vtu"}, 1, {"--max-squares 100"});
    // 256 pixels.
    sb.refuse({"mesh", img, "--max-pixels", "255", "-o", "m.vtu"}, 1, {"exceed the limit of 255 pixels"});
    // Headers claiming huge images are refused before any pixel is read or
    // allocated: the files hold no pixel data at all.
    const std::string huge_pgm = sb.input("huge.pgm", "P5\n100000 100000\n255\n").string();
    sb.refuse({"mesh", huge_pgm, "-o", "m.vtu"}, 1, {"100000 x 100000", "exceed the limit of 268435456 pixels"});
    const std::string widest = sb.input("wide.pgm", "P5\n4294967295 4294967295\n255\n").string();
    sb.refuse({"mesh", widest, "-o", "m.vtu"}, 1, {"exceed the limit"});
    const std::string huge_png =
        sb.input("huge.png", png_signature + png_ihdr(100000, 100000, 8, 0) +
                                 png_chunk("IDAT", zlib_stored(std::string(10, '\0'))) + png_chunk("IEND", ""))
            .string();
    sb.refuse({"mesh", huge_png, "-o", "m.vtu"}, 1, {"huge.png", "exceed the limit"});
}

namespace {
// An input file that `warpmesh mesh FILE -o m.vtu` must refuse (exit 1,
// "error: image 'FILE'", nothing written) with each of `needles` in the message.
struct BrokenImage {
    const char* name;
    std::string bytes;
    std::vector<std::string> needles;
};
void refuse_images(const Sandbox& sb, const std::vector<BrokenImage>& cases) {
    for (const auto& c : cases) {
        const std::string path = sb.input(c.name, c.bytes).string();
        const Result r = sb.refuse({"mesh", path, "-o", "m.vtu"}, 1, {"error: image '" + path + "'"});
        for (const auto& n : c.needles) {
            BOOST_TEST_INFO(c.name << ": " << r.err << " expected to contain: " << n);
            BOOST_TEST(r.err.find(n) != std::string::npos);
        }
    }
}
}  // namespace

// --- broken PGM ---------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(malformed_and_truncated_pgm) {
    Sandbox sb;
    const std::vector<BrokenImage> cases = {
        {"empty.pgm", "", {"empty file"}},
        {"magic_only.pgm", "P5", {"malformed header"}},
        {"no_space.pgm", "P5x 2 2 255\n", {"no whitespace after the magic number"}},
        {"no_height.pgm", "P5\n4\n", {"malformed header", "height"}},
        {"no_maxval.pgm", "P2 4 4", {"malformed header", "maxval"}},
        {"letters.pgm", "P5\nfour 4\n255\n", {"malformed header", "width"}},
        {"negative.pgm", "P5\n-4 4\n255\n", {"malformed header", "width"}},
        {"junk.pgm", "P5\n4x 4\n255\n", {"junk after width"}},
        {"zero_width.pgm", "P5\n0 4\n255\n", {"zero width or height"}},
        {"maxval0.pgm", "P5\n2 2\n0\n\x01\x01\x01\x01", {"maxval 0 is not in 1..65535"}},
        {"maxval_70000.pgm", "P5\n2 2\n70000\n", {"maxval 70000 is not in 1..65535"}},
        {"overflow.pgm", "P5\n99999999999999999999999 2\n255\n", {"width exceeds"}},
        {"no_raster.pgm", "P5\n4 4\n255", {"truncated data"}},
        {"short_raster.pgm", "P5\n4 4\n255\n0123456789", {"truncated data", "expected 16 bytes", "found 10"}},
        {"short_raster16.pgm", "P5\n2 2\n65535\n\x01\x02\x03\x04\x05\x06\x07", {"truncated data", "expected 8 bytes"}},
        {"short_p2.pgm", "P2\n3 2\n255\n1 2 3 4\n", {"truncated data", "expected 6 samples, found 4"}},
        {"p2_letter.pgm", "P2\n2 2\n255\n1 2 x 4\n", {"malformed pixel data"}},
        {"p2_above_maxval.pgm", "P2\n2 2\n100\n1 2 101 4\n", {"is 101, above maxval 100"}},
        {"p5_above_maxval.pgm", pgm_p5(2, 2, 1000, {1, 2, 3, 1001}), {"above maxval 1000"}},
        {"p6.ppm", "P6\n2 2\n255\n" + std::string(12, 'a'), {"unsupported format", "Netpbm P6"}},
        {"p1.pbm", "P1\n2 2\n0 1 1 0\n", {"unsupported format", "Netpbm P1"}},
        {"jpeg.pgm", "\xff\xd8\xff\xe0 not really", {"unsupported format", "JPEG"}},
        {"gif.pgm", "GIF89a....", {"unsupported format", "GIF"}},
        {"text.pgm", "hello, world\n", {"unsupported format", "expected PGM (P2/P5) or PNG"}},
    };
    refuse_images(sb, cases);
}

// --- broken PNG ---------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(malformed_truncated_and_unsupported_png) {
    Sandbox sb;
    // The builders make a valid file first: it must mesh.
    const std::string good = sb.input("good.png", png_gray8(6, 5)).string();
    {
        const Result r = sb.run({"mesh", good, "--iso", "100", "-o", "m.vtu", "--quiet"});
        BOOST_TEST_INFO(r.err);
        BOOST_TEST(r.code == 0);
        fs::remove(sb.out / "m.vtu");
    }
    const std::string valid = png_gray8(6, 5);
    const std::string idat = png_chunk("IDAT", zlib_stored(std::string(5 * 7, '\0')));
    const std::string iend = png_chunk("IEND", "");
    const std::vector<BrokenImage> cases = {
        {"signature_only.png", png_signature, {"corrupt PNG"}},
        {"half_signature.png", png_signature.substr(0, 5), {"unsupported format"}},
        {"bad_ihdr_crc.png", png_signature + png_ihdr(6, 5, 8, 0, true) + idat + iend, {"corrupt PNG", "CRC"}},
        {"depth3.png", png_signature + png_ihdr(6, 5, 3, 0) + idat + iend, {"corrupt PNG", "bit depth"}},
        {"depth32.png", png_signature + png_ihdr(6, 5, 32, 0) + idat + iend, {"corrupt PNG", "bit depth"}},
        {"rgb_depth4.png", png_signature + png_ihdr(6, 5, 4, 2) + idat + iend, {"corrupt PNG"}},
        {"color_type5.png", png_signature + png_ihdr(6, 5, 8, 5) + idat + iend, {"corrupt PNG", "color type"}},
        {"zero_width.png", png_signature + png_ihdr(0, 5, 8, 0) + idat + iend, {"corrupt PNG"}},
        {"no_idat.png", png_signature + png_ihdr(6, 5, 8, 0) + iend, {"corrupt PNG"}},
        {"palette_without_plte.png", png_signature + png_ihdr(6, 5, 8, 3) + idat + iend, {"corrupt PNG"}},
        {"truncated_in_idat.png", valid.substr(0, valid.size() - 30), {"corrupt PNG"}},
        {"truncated_in_ihdr.png", valid.substr(0, 20), {"corrupt PNG"}},
        {"short_idat.png", png_signature + png_ihdr(6, 5, 8, 0) + png_chunk("IDAT", zlib_stored(std::string(12, '\0'))) + iend,
         {"corrupt PNG"}},
        {"garbage_idat.png", png_signature + png_ihdr(6, 5, 8, 0) + png_chunk("IDAT", "this is not zlib data") + iend,
         {"corrupt PNG"}},
    };
    refuse_images(sb, cases);
}

// --- images too small to mesh --------------------------------------------------------

BOOST_AUTO_TEST_CASE(one_pixel_wide_images_are_refused) {
    Sandbox sb;
    for (const auto& [w, h] : {std::pair{1, 5}, std::pair{5, 1}, std::pair{1, 1}}) {
        const std::string path =
            sb.input("thin.pgm", pgm_p5(w, h, 255, std::vector<int>(static_cast<std::size_t>(w * h), 255))).string();
        sb.refuse({"mesh", path, "-o", "m.vtu"}, 1,
                  {std::to_string(w) + " x " + std::to_string(h) + " pixels", "at least 2 x 2"});
        sb.refuse({"mesh", path, "--label", "nonzero", "-o", "m.vtu"}, 1, {"at least 2 x 2"});
    }
    const std::string png = sb.input("thin.png", png_gray8(7, 1)).string();
    sb.refuse({"mesh", png, "-o", "m.vtu"}, 1, {"7 x 1 pixels", "at least 2 x 2"});
}

// --- level set problems ---------------------------------------------------------------

BOOST_AUTO_TEST_CASE(empty_region_writes_nothing) {
    Sandbox sb;
    const std::string black = sb.input("black.pgm", pgm_p5(6, 6, 255, std::vector<int>(36, 0))).string();
    const std::string img = sb.input("disc.pgm", disc_pgm(12, 12)).string();
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{}, {"--graded"}, {"--diagonal", "maxmin"}, {"--iso", "10"}}) {
        std::vector<std::string> args = {"mesh", black, "-o", "m.vtu", "--report", "r.json", "--also", "m.svg"};
        args.insert(args.end(), extra.begin(), extra.end());
        sb.refuse(args, 1, {"region is empty", "nothing written"});
    }
    // Nothing above an iso value above the maximum, nothing below one below the minimum.
    sb.refuse({"mesh", img, "--iso", "300", "-o", "m.vtu"}, 1, {"region is empty"});
    sb.refuse({"mesh", img, "--iso", "-1", "--inside", "below", "-o", "m.vtu"}, 1, {"region is empty"});
    // A region that exists but has no whole triangle at this spacing.
    std::vector<int> dot(100, 0);
    dot[55] = 255;
    const std::string one = sb.input("dot.pgm", pgm_p5(10, 10, 255, dot)).string();
    sb.refuse({"mesh", one, "--spacing", "3", "-o", "m.vtu"}, 1, {"region is empty", "smaller --spacing"});
}

BOOST_AUTO_TEST_CASE(labels_not_in_the_image) {
    Sandbox sb;
    // 8 x 8 of label 3 with a 3 x 3 block of label 5.
    std::vector<int> px(64, 3);
    for (int r = 2; r < 5; ++r)
        for (int c = 2; c < 5; ++c) px[static_cast<std::size_t>(r * 8 + c)] = 5;
    const std::string img = sb.input("labels.pgm", pgm_p5(8, 8, 255, px)).string();
    sb.refuse({"mesh", img, "--label", "7", "-o", "m.vtu"}, 1, {"none of the labels {7} is present", "3", "5"});
    sb.refuse({"mesh", img, "--label", "7,9-12", "-o", "m.vtu"}, 1, {"none of the labels"});
    sb.refuse({"mesh", img, "--label", "70000", "-o", "m.vtu"}, 1, {"70000"});
    sb.refuse({"mesh", img, "--label", "abc", "-o", "m.vtu"}, 1, {"abc"});
    sb.refuse({"mesh", img, "--label", "", "-o", "m.vtu"}, 1, {"label"});
    sb.refuse({"mesh", img, "--label", "-3", "-o", "m.vtu"}, 1, {"-3"});
    const std::string zeros = sb.input("zeros.pgm", pgm_p5(4, 4, 255, std::vector<int>(16, 0))).string();
    sb.refuse({"mesh", zeros, "--label", "nonzero", "-o", "m.vtu"}, 1, {"zeros.pgm"});
    // Present labels still mesh.
    const Result ok = sb.run({"mesh", img, "--label", "5,7", "-o", "m.vtu", "--quiet"});
    BOOST_TEST_INFO(ok.err);
    BOOST_TEST(ok.code == 0);
}

BOOST_AUTO_TEST_CASE(non_finite_and_absurd_shapes) {
    Sandbox sb;
    sb.refuse({"mesh", "--shape", "circle:0,0,nan", "-o", "m.vtu"}, 1, {"circle:0,0,nan", "finite"});
    sb.refuse({"mesh", "--shape", "circle:inf,0,1", "-o", "m.vtu"}, 1, {"finite"});
    sb.refuse({"mesh", "--shape", "ellipse:0,0,1e400,1", "-o", "m.vtu"}, 1, {"ellipse"});
    sb.refuse({"mesh", "--shape", "circle:0,0,-1", "-o", "m.vtu"}, 1, {"radius must be positive"});
    sb.refuse({"mesh", "--shape", "circle:0,0", "-o", "m.vtu"}, 1, {"circle:0,0"});
    sb.refuse({"mesh", "--shape", "union(circle:0,0,1", "-o", "m.vtu"}, 1, {"union(circle:0,0,1"});
    sb.refuse({"mesh", "--shape", "blob:1,2,3", "-o", "m.vtu"}, 1, {"blob"});
    // Finite parameters whose lattice is not: refused by the lattice size,
    // not by an overflow.
    sb.refuse({"mesh", "--shape", "circle:0,0,1e300", "-o", "m.vtu"}, 1, {"--max-squares"});
    sb.refuse({"mesh", "--shape", "rect:-1e308,0,1e308,1", "-o", "m.vtu"}, 1, {"--max-squares"});
    // A small shape far from the origin: lattice points x0 + i s would round
    // onto each other (this used to write a mesh of zero-area triangles).
    sb.refuse({"mesh", "--shape", "circle:1e300,1e300,1", "-o", "m.vtu"}, 1, {"too small for coordinates"});
    sb.refuse({"mesh", "--shape", "circle:1e15,0,3", "--spacing", "0.1", "-o", "m.vtu"}, 1,
              {"too small for coordinates"});
    BOOST_TEST(sb.run({"mesh", "--shape", "circle:1e6,0,3", "--spacing", "0.1", "-o", "m.vtu", "--quiet"}).code == 0);
    fs::remove(sb.out / "m.vtu");
    // A tiny shape at a tiny spacing: every coordinate is representable, but
    // triangle areas would underflow to 0 (this used to write such a mesh).
    sb.refuse({"mesh", "--shape", "rect:0,0,1e-300,1e-300", "--spacing", "1e-301", "-o", "m.vtu"}, 1,
              {"outside 1e-100 .. 1e100"});
}

// --- paths ---------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(unreadable_inputs) {
    Sandbox sb;
    sb.refuse({"mesh", sb.in.string(), "-o", "m.vtu"}, 1, {"is a directory"});
    sb.refuse({"mesh", (sb.in / "missing.pgm").string(), "-o", "m.vtu"}, 1, {"missing.pgm", "No such file"});
    sb.refuse({"mesh", "", "-o", "m.vtu"}, 2, {});  // an empty argument is no input
}

BOOST_AUTO_TEST_CASE(unwritable_outputs) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(12, 12)).string();
    sb.refuse({"mesh", img, "-o", "m.xyz"}, 1, {"m.xyz", "unknown output format '.xyz'"});
    sb.refuse({"mesh", img, "-o", "mesh"}, 1, {"unknown output format"});
    sb.refuse({"mesh", img, "-o", "m.vtu", "--also", "m.stl"}, 1, {"m.stl", "unknown output format"});
    sb.refuse({"mesh", img, "-o", "no/such/dir/m.vtu"}, 1, {"no/such/dir", "not a directory"});
    sb.refuse({"mesh", img, "-o", "m.vtu", "--also", "nodir/m.msh"}, 1, {"nodir", "not a directory"});
    // An input file used as a directory.
    sb.refuse({"mesh", img, "-o", img + "/m.vtu"}, 1, {"not a directory"});
    // An output path that is an existing directory: the mesh is written to a
    // temporary that cannot be renamed onto it; the temporary is removed.
    fs::create_directory(sb.out / "d.vtu");
    sb.refuse({"mesh", img, "-o", "d.vtu"}, 1, {"cannot write 'd.vtu'", "is a directory"});
    // Several outputs are all-or-nothing: a bad second one means no first one.
    sb.refuse({"mesh", img, "-o", "m.vtu", "--also", "d.vtu"}, 1, {"cannot write 'd.vtu'", "is a directory"});
    fs::create_directory(sb.out / "r.json");
    sb.refuse({"mesh", img, "-o", "d.vtu", "--report", "r.json"}, 1, {"cannot write"});
    BOOST_TEST(fs::is_empty(sb.out / "d.vtu"));
    sb.refuse({"mesh", img, "-o", ".", "--quiet"}, 1, {"cannot write '.'"});
}

BOOST_AUTO_TEST_CASE(a_write_failing_midway_leaves_nothing) {
    Sandbox sb;
    const std::string img = sb.input("disc.pgm", disc_pgm(64, 64)).string();
    // RLIMIT_FSIZE of 2 blocks (1 KiB) with SIGXFSZ ignored: writes past it
    // fail with EFBIG, like a full disk, after the temporary file was created
    // and partly written.  Each format, and a stale file under the name is
    // neither replaced nor removed.
    for (const char* out : {"m.vtu", "m.msh", "m.svg", "m.node"}) {
        sb.refuse({"mesh", img, "-o", out, "--quiet"}, 1, {std::string("cannot write '") + out + "'"},
                  "trap '' XFSZ; ulimit -f 2;");
    }
    write_bytes(sb.out / "old.vtu", "old content");
    sb.refuse({"mesh", img, "-o", "old.vtu", "--quiet"}, 1, {"cannot write 'old.vtu'"}, "trap '' XFSZ; ulimit -f 2;");
    BOOST_TEST(slurp(sb.out / "old.vtu") == "old content");
    // The report is small and fits, the mesh does not: no report either.
    sb.refuse({"mesh", img, "--report", "r.json", "-o", "m.vtu", "--quiet"}, 1, {"cannot write 'm.vtu'"},
              "trap '' XFSZ; ulimit -f 2;");
    // Two meshes, the first small enough to be written, the second not: the
    // first must not appear either (outputs are staged, then renamed together).
    BOOST_TEST(sb.run({"mesh", img, "-o", "small.msh", "--also", "big.svg", "--quiet"}).code == 0);
    const auto small = fs::file_size(sb.out / "small.msh"), big = fs::file_size(sb.out / "big.svg");
    fs::remove(sb.out / "small.msh");
    fs::remove(sb.out / "big.svg");
    const auto limit_blocks = small / 512 + 1;  // /bin/sh's ulimit -f counts 512-byte blocks (dash, POSIX)
    BOOST_TEST_INFO("small.msh " << small << " bytes, big.svg " << big << " bytes");
    BOOST_REQUIRE(limit_blocks * 512 < big);
    sb.refuse({"mesh", img, "-o", "small.msh", "--also", "big.svg", "--quiet"}, 1, {"cannot write 'big.svg'"},
              "trap '' XFSZ; ulimit -f " + std::to_string(limit_blocks) + ";");
}

// --- region touching the border --------------------------------------------------------

BOOST_AUTO_TEST_CASE(region_touching_the_border_is_closed_with_tag_2) {
    Sandbox sb;
    // Left half bright: the region reaches the image's left, top and bottom
    // borders, where the lattice border closes it.
    std::vector<int> px;
    for (int r = 0; r < 8; ++r)
        for (int c = 0; c < 10; ++c) px.push_back(c < 5 ? 255 : 0);
    const std::string img = sb.input("half.pgm", pgm_p5(10, 8, 255, px)).string();
    const Result r = sb.run({"mesh", img, "-o", "m.msh", "--quiet"});
    BOOST_TEST_INFO(r.err);
    BOOST_REQUIRE(r.code == 0);
    const std::string msh = slurp(sb.out / "m.msh");
    BOOST_TEST(msh.find("\"domain_border\"") != std::string::npos);
    BOOST_TEST(msh.find("\"boundary\"") != std::string::npos);
    // A region strictly inside has no domain border.
    const std::string disc = sb.input("disc.pgm", disc_pgm(16, 16)).string();
    BOOST_REQUIRE(sb.run({"mesh", disc, "-o", "d.msh", "--quiet"}).code == 0);
    BOOST_TEST(slurp(sb.out / "d.msh").find("\"domain_border\"") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(coarse_spacing_warns_with_a_spacing_that_resolves_and_optimize_reports_its_section) {
    Sandbox sb;
    // A disc of radius 1 at the default spacing 1 is a 4-triangle diamond.
    const Result coarse = sb.run({"mesh", "--shape", "circle:0,0,1", "-o", "d.vtu", "--quiet"});
    BOOST_TEST(coarse.code == 0);
    BOOST_TEST(coarse.err.find("too coarse") != std::string::npos);
    BOOST_TEST(coarse.err.find("spacing 0.35 or less") != std::string::npos);
    const Result fine = sb.run({"mesh", "--shape", "circle:0,0,1", "--spacing", "0.35", "-o", "d.vtu", "--quiet"});
    BOOST_TEST(fine.err.find("too coarse") == std::string::npos);

    const Result o = sb.run({"mesh", "--shape", "ellipse:0,0,30,18", "--optimize", "-o", "e.msh", "--report", "r.json"});
    BOOST_TEST(o.code == 0);
    BOOST_TEST(o.out.find("optimize             min angle") != std::string::npos);
    const std::string json = slurp(sb.out / "r.json");
    for (const char* key : {"\"optimize\": {", "\"certified_floor_deg\"", "\"min_angle_after_deg\"", "\"optimize\": 0"})
        BOOST_TEST(json.find(key) != std::string::npos, key);
}

// --- issue 27 item 3: bounded memory on hostile inputs ------------------------
//
// Each case exits 1 with one line naming the problem (and the option that
// raises a limit), writes nothing, and peaks below the default bound of
// --max-memory (2048 MB): the largest resident size of the children run so
// far (getrusage RUSAGE_CHILDREN), checked after each case.

namespace {

constexpr long bound_kb = 2048L * 1024;

long children_peak_kb() {
    rusage ru{};
    getrusage(RUSAGE_CHILDREN, &ru);
    return ru.ru_maxrss;
}

void one_line_below_the_bound(const Result& r) {
    BOOST_TEST(std::count(r.err.begin(), r.err.end(), '\n') == 1, r.err);
    BOOST_TEST(children_peak_kb() < bound_kb, "peak " << children_peak_kb() << " kB");
}

std::string nhdr(int n, const std::string& data_file) {
    return "NRRD0004\ntype: uchar\ndimension: 2\nsizes: " + std::to_string(n) + " " + std::to_string(n) +
           "\nencoding: raw\ndata file: " + data_file + "\n";
}

}  // namespace

// Read without limit before: 11.7 GB resident at 60 s on /dev/zero, 8.2 GB on
// /dev/urandom.
BOOST_AUTO_TEST_CASE(detached_nrrd_data_file_on_dev_zero_or_dev_urandom_is_refused_without_reading_it) {
    Sandbox sb;
    for (const std::string dev : {"/dev/zero", "/dev/urandom"}) {
        // 16384^2 voxels: over the memory bound before anything is read.
        const std::string big = sb.input("big.nhdr", nhdr(16384, dev)).string();
        one_line_below_the_bound(sb.refuse({"mesh", big, "-o", "m.vtu"}, 1, {"big.nhdr", "--max-memory limit of 2048 MB"}));
        // Within the bound: refused as a device, never opened.
        one_line_below_the_bound(
            sb.refuse({"mesh", big, "-o", "m.vtu", "--max-memory", "8192"}, 1, {dev, "is a device, not a regular file"}));
        const std::string small = sb.input("small.nhdr", nhdr(64, dev)).string();
        one_line_below_the_bound(sb.refuse({"mesh", small, "-o", "m.vtu"}, 1, {dev, "is a device"}));
    }
    one_line_below_the_bound(sb.refuse({"mesh", "/dev/zero", "-o", "m.vtu"}, 1, {"'/dev/zero'", "is a device"}));
}

// Before: 261 KB of gzip (under the compression-ratio check) took 6.4 GB and
// 37 s before "region is empty".
BOOST_AUTO_TEST_CASE(gzip_nrrd_of_16384_squared_zeros_is_refused_before_inflating) {
    Sandbox sb;
    const int n = 16384;
    std::string gz;
    z_stream zs{};
    BOOST_REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY) == Z_OK);
    std::vector<unsigned char> row(static_cast<std::size_t>(n) * 64, 0), out(1 << 16);
    for (int r = 0; r < n / 64; ++r) {
        zs.next_in = row.data();
        zs.avail_in = static_cast<uInt>(row.size());
        const int flush = r + 1 == n / 64 ? Z_FINISH : Z_NO_FLUSH;
        do {
            zs.next_out = out.data();
            zs.avail_out = static_cast<uInt>(out.size());
            deflate(&zs, flush);
            gz.append(reinterpret_cast<const char*>(out.data()), out.size() - zs.avail_out);
        } while (zs.avail_out == 0);
    }
    deflateEnd(&zs);
    BOOST_TEST(gz.size() < 300000u);  // the 261 KB
    const std::string header = "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 16384 16384\nencoding: gzip\n\n";
    const std::string f = sb.input("zeros.nrrd", header + gz).string();
    one_line_below_the_bound(sb.refuse({"mesh", f, "-o", "m.vtu"}, 1, {"zeros.nrrd", "--max-memory limit of 2048 MB"}));
}

// Before: a 4096^2 image of 65 536 labels with --materials all --graded
// peaked at 3.0 GB.  Its material field alone is over the bound: refused
// before it is built.
BOOST_AUTO_TEST_CASE(label_image_of_65536_labels_with_materials_graded_is_refused_before_its_field) {
    Sandbox sb;
    const int w = 4096;
    std::string img = "P5\n4096 4096\n65535\n";
    img.reserve(img.size() + 2u * w * w);
    for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(w * w); ++k) {
        const std::uint32_t label = k * 40503u % 65536u;  // every label, scattered
        img += static_cast<char>(label >> 8);
        img += static_cast<char>(label & 255);
    }
    const std::string f = sb.input("labels.pgm", img).string();
    one_line_below_the_bound(sb.refuse({"mesh", f, "--materials", "all", "--graded", "-o", "m.vtu"}, 1,
                                       {"labels.pgm", "4096 x 4096 pixels", "--max-memory limit of 2048 MB"}));
}

// The meshing stage's own check: a lattice whose squares are over the bound
// is refused before it is sampled, naming --max-memory and --spacing.
BOOST_AUTO_TEST_CASE(lattice_over_the_memory_bound_is_refused_before_meshing) {
    Sandbox sb;
    const std::string disc = sb.input("disc.pgm", disc_pgm(16, 16)).string();
    one_line_below_the_bound(sb.refuse({"mesh", disc, "--spacing", "0.001", "-o", "m.vtu"}, 1,
                                       {"meshing needs about", "--max-memory limit of 2048 MB", "--spacing"}));
    one_line_below_the_bound(sb.refuse({"mesh", disc, "--spacing", "0.02", "--max-memory", "20", "-o", "m.vtu"}, 1,
                                       {"--max-memory limit of 20 MB"}));
    BOOST_TEST(sb.run({"mesh", disc, "--spacing", "0.02", "-o", "m.vtu", "--quiet"}).code == 0);
    sb.refuse({"mesh", disc, "--max-memory", "0", "-o", "x.vtu"}, 2, {"--max-memory"});
}

// Under a memory limit the machine imposes (here ulimit -v) below
// --max-memory, an allocation fails: the message says that the machine
// allows less than --max-memory (it used to say "try a larger --spacing"),
// and a --max-memory within the machine's limit refuses cleanly instead.
// Not under AddressSanitizer, which reserves more address space than any
// such limit.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPMESH_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define WARPMESH_TEST_ASAN 1
#endif
BOOST_AUTO_TEST_CASE(out_of_memory_under_a_ulimit_says_to_lower_max_memory) {
#ifndef WARPMESH_TEST_ASAN
    Sandbox sb;
    const std::string img = std::string(WARPMESH_SOURCE_DIR) + "/mesher/examples/brain_axial_s128_labels16.pgm";
    const std::vector<std::string> args = {"mesh", img, "--label", "4", "--spacing", "0.04", "--threads", "1", "-o", "m.vtu"};
    auto with = [&](const std::string& mb) {
        auto a = args;
        a.insert(a.end(), {"--max-memory", mb});
        return a;
    };
    one_line_below_the_bound(sb.refuse(with("8192"), 1, {"out of memory", "lower --max-memory"}, "ulimit -v 200000;"));
    one_line_below_the_bound(sb.refuse(with("100"), 1, {"meshing needs about", "--max-memory limit of 100 MB"},
                                       "ulimit -v 200000;"));
#endif
}
