// The option tables (pipeline/options.hpp) are what the command line's help
// and parser are made of, and the library's messages name options in its own
// words: every entry of the 2D and 3D tables is in `warpmesh mesh --help` /
// `warpmesh mesh3d --help` and accepted by that command's parser; a bad value
// of every entry is an OptionError naming the entry by its library name (no
// flag), which the command line prints with its flag; the enums' names read
// both ways.  (Python's side: tests/python/test_module_options.py.)
#define BOOST_TEST_MODULE options
#include <boost/test/unit_test.hpp>

#include "support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;

namespace {

struct Run {
    int code = -1;
    std::string out, err;
};

// `warpmesh ARGS` (each argument single-quoted, none contains a quote).
Run run(const std::string& args) {
    const fs::path dir = fs::temp_directory_path() / ("warpmesh-options-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string cmd = "cd '" + dir.string() + "' && '" + WARPMESH_EXE + "' " + args + " >'" + (dir / "out").string() +
                            "' 2>'" + (dir / "err").string() + "'";
    const int status = std::system(cmd.c_str());
    Run r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = warpmesh::testing::slurp(dir / "out");
    r.err = warpmesh::testing::slurp(dir / "err");
    fs::remove_all(dir);
    return r;
}

// A value of the entry's kind that its setter reads ("" for flags: none is given).
std::string good_text(const OptionDoc& d) {
    switch (d.kind) {
        case OptionKind::flag: return "";
        case OptionKind::number: return "1";
        case OptionKind::integer: return "2";  // in every integer entry's range (band >= 2, max_cell a power of two)
        case OptionKind::choice: return std::string(d.choices.front());
        case OptionKind::pairs: return "1=4";
        case OptionKind::text: return "x";
    }
    return "";
}

// A value its setter refuses.
std::string bad_text(const OptionDoc& d) { return d.kind == OptionKind::flag ? "maybe" : "x!"; }

template <class Options>
void check_table(const OptionTable<Options>& table, const std::string& command) {
    const Run help = run(command + " --help");
    BOOST_TEST(help.code == 0);
    for (const auto& entry : table.options) {
        const std::string flag = cli_flag(entry);
        BOOST_TEST_INFO(command << " " << flag);
        BOOST_TEST(help.out.find("\n  " + flag + " ") != std::string::npos);  // its line in the help
        if (!entry.off_flag.empty()) BOOST_TEST(help.out.find(" / " + std::string(entry.off_flag) + "\n") != std::string::npos);
        // The parser takes it: the refusal is about the missing input, not the flag.
        const std::string value = good_text(entry);
        const Run r = run(command + " " + flag + (value.empty() ? "" : " '" + value + "'") + " --quiet --report r.json");
        BOOST_TEST_INFO(command << " " << flag << ": " << r.err);
        BOOST_TEST(r.err.find("give exactly one of") != std::string::npos);
        // A bad value: an OptionError in the library's words, naming the entry.
        Options o;
        GivenOptions given;
        try {
            table.set(o, given, entry.name, bad_text(entry));
            BOOST_TEST(false, entry.name << " took '" << bad_text(entry) << "'");
        } catch (const OptionError& e) {
            BOOST_TEST_INFO(e.what());
            BOOST_TEST(e.option() == entry.name);
            BOOST_TEST(std::string(e.what()).rfind(std::string(entry.name) + " expects", 0) == 0);
            BOOST_TEST(std::string(e.what()).find("--") == std::string::npos);
        }
    }
    // Nothing else is the library's: an unknown name is refused.
    Options o;
    GivenOptions given;
    BOOST_CHECK_THROW(table.set(o, given, "no_such_option", "1"), OptionError);
}

}  // namespace

BOOST_AUTO_TEST_CASE(every_2d_entry_is_in_the_help_and_the_parser_of_mesh) { check_table(mesh2d_option_table(), "mesh"); }

BOOST_AUTO_TEST_CASE(every_3d_entry_is_in_the_help_and_the_parser_of_mesh3d_and_only_3d_help_is_printed) {
    check_table(mesh3d_option_table(), "mesh3d");
    const Run help = run("mesh3d --help");
    // 3D help only, naming the default rule's certificate (issue 50).
    for (const char* flag : {"--diagonal", "--max-cell", "--max-size-of", "--slice", "--svg-color", "--optimize"}) {
        BOOST_TEST_INFO(flag);
        BOOST_TEST(help.out.find(flag) == std::string::npos);
    }
    BOOST_TEST(help.out.find("proofs/bcc_delaunay.cert") != std::string::npos);
    // Graded meshes (issue 48).
    for (const char* flag : {"\n  --graded", "\n  --max-size H", "\n  --grading G"}) {
        BOOST_TEST_INFO(flag);
        BOOST_TEST(help.out.find(flag) != std::string::npos);
    }
    // Several materials (issue 47): a volume's labels, analytic materials, the background.
    for (const char* flag : {"\n  --materials all|L,...", "\n  --shapes T=S;T=S...", "\n  --background drop|keep"}) {
        BOOST_TEST_INFO(flag);
        BOOST_TEST(help.out.find(flag) != std::string::npos);
    }
    // And the 2D help does not list 3D's face rule.
    BOOST_TEST(run("mesh --help").out.find("--face-rule") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_2d_help_no_longer_says_the_fan_rule_is_not_for_several_materials) {
    // Issue 50: the fan rule meshes several materials (test_fan_rule); its help said it did not.
    const Run help = run("mesh --help");
    BOOST_TEST(help.out.find("not with several materials") == std::string::npos);
    BOOST_TEST(help.out.find("one region or several materials") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(library_messages_name_options_in_library_words_and_the_cli_prints_flags) {
    MeshOptions o;
    o.spacing = -1;
    try {
        validate(o);
        BOOST_TEST(false);
    } catch (const OptionError& e) {
        BOOST_TEST(e.option() == "spacing");
        BOOST_TEST(std::string(e.what()) == "spacing must be positive and at most 1e9 (got -1)");
    }
    o = MeshOptions{};
    o.lattice = LatticeMetric::rhombic;
    o.rule = DiagonalRule::fan;
    try {
        validate(o);
        BOOST_TEST(false);
    } catch (const OptionError& e) {
        BOOST_TEST(std::string(e.what()) ==
                   "rule=fan is not available with lattice=rhombic (uniform meshes with rule separating or maxmin only)");
        const auto docs = mesh2d_option_table().docs();
        BOOST_TEST(spell_options(e.message(), docs, Spelling::cli) ==
                   "--diagonal fan is not available with --lattice rhombic (uniform meshes with --diagonal separating "
                   "or maxmin only)");
        BOOST_TEST(spell_options(e.message(), docs, Spelling::python) ==
                   "rule='fan' is not available with lattice='rhombic' (uniform meshes with rule separating or maxmin "
                   "only)");
    }
    // Contradictions that only a client's "given" shows: grading 2 without graded.
    GivenOptions given{"grading"};
    BOOST_CHECK_THROW(validate(MeshOptions{}, given), OptionError);
    BOOST_CHECK_NO_THROW(validate(MeshOptions{}));
    // The command line prints the same message with its flags.
    const Run r = run("mesh --shape circle:0,0,1 --lattice rhombic --diagonal fan -o m.vtu");
    BOOST_TEST(r.code == 2);
    BOOST_TEST(r.err == "warpmesh: --diagonal fan is not available with --lattice rhombic (uniform meshes with "
                        "--diagonal separating or maxmin only)\n");
    // An error of the run (exit 1) too.
    const Run big = run("mesh --shape circle:0,0,10 --max-squares 100 -o m.vtu");
    BOOST_TEST(big.code == 1);
    BOOST_TEST(big.err.find("more than --max-squares 100 (use a larger --spacing)") != std::string::npos);
    // 3D: the library's words, the command line's flag.
    Mesh3dOptions o3;
    o3.spacing = 0;
    BOOST_CHECK_EXCEPTION(validate(o3), OptionError, [](const OptionError& e) {
        return std::string(e.what()) == "spacing must be positive and finite (got 0)";
    });
    const Run r3 = run("mesh3d --shape sphere:0,0,0,1 --spacing 0 -o m.vtu");
    BOOST_TEST(r3.code == 2);
    BOOST_TEST(r3.err == "warpmesh: --spacing must be positive and finite (got 0)\n");
}

BOOST_AUTO_TEST_CASE(marks_are_only_option_names) {
    const auto spell = [](std::string_view n, std::string_view v) { return "<" + std::string(n) + "|" + std::string(v) + ">"; };
    BOOST_TEST(spell_marks("a {max_size} b {graded=true} c", spell) == "a <max_size|> b <graded|true> c");
    // Not marks: braces around anything but a name (set literals, numbers, empty values).
    BOOST_TEST(spell_marks("labels {7} {x=} {A} {} {", spell) == "labels {7} {x=} {A} {} {");
}

BOOST_AUTO_TEST_CASE(enum_names_read_both_ways) {
    for (const auto& n : diagonal_rule_names) BOOST_TEST((value_of(diagonal_rule_names, name_of(diagonal_rule_names, n.value)) == n.value));
    for (const auto& n : lattice_metric_names) BOOST_TEST((value_of(lattice_metric_names, n.name) == n.value));
    for (const auto& n : face_rule_names) BOOST_TEST((value_of(face_rule_names, n.name) == n.value));
    BOOST_TEST(!value_of(diagonal_rule_names, "Separating").has_value());
    BOOST_TEST(std::string(rule_name(DiagonalRule::fan)) == "fan");
    BOOST_TEST(std::string(face_rule_name(FaceRule::delaunay)) == "delaunay");
}
