// prove_main.cpp — `warpmesh prove`: arguments, one proof per rule, and the
// files proofs/<rule>.cert and proofs/key_table.txt; with `--lattice rhombic`
// the rhombic metric's proofs/rhombic_<rule>.cert (maxmin and separating, sign
// keys).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "warpmesh/key_list.hpp"
#include "warpmesh/prove.hpp"

namespace warpmesh {

namespace {

// Appends the key lines of `cert` (rule `name`) to the key table at `path`,
// truncating it first when `fresh`: one line per key.
void write_key_table(const std::string& path, const std::string& name, const std::string& cert, bool fresh) {
    std::ofstream tab(path, fresh ? std::ios::trunc : std::ios::app);
    if (fresh)
        tab << "# rule key flat min_cot max_cot   (see proofs/README.md; every angle a of the chosen triangles\n"
            << "# of every configuration of the key has max_cot <= cot(a) <= min_cot)\n";
    std::istringstream cs(cert);
    for (std::string line; std::getline(cs, line);) {
        if (line.rfind("key ", 0) != 0) continue;
        std::istringstream ls(line);
        std::string w, id, code, flat, m, qmin, qmax;
        ls >> w >> id >> code >> flat >> m >> qmin >> qmax;
        tab << name << ' ' << code << ' ' << (flat == "1" ? "flat" : "any") << ' ' << qmin << ' '
            << (qmin == "inverted" ? "-" : qmax) << "\n";
    }
}

}  // namespace

int prove_main(int argc, char** argv) {
    std::string out = "proofs";
    std::vector<int> subset, jsubset;
    bool use_subset = false, sign_subset = false, junction_subset = false;
    LatticeMetric metric = LatticeMetric::square;
    std::vector<DiagonalRule> rules{DiagonalRule::maxmin, DiagonalRule::separating, DiagonalRule::fan};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "prove") continue;
        if (a == "--out" && i + 1 < argc) out = argv[++i];
        else if (a == "--threads" && i + 1 < argc) {
            prover::set_threads(argv[++i]);
        } else if (a == "--rule" && i + 1 < argc) {  // one rule only (development; key_table.txt then holds it alone)
            const std::optional<DiagonalRule> r = value_of(diagonal_rule_names, argv[++i]);
            if (!r) {
                std::fprintf(stderr, "warpmesh prove: --rule expects maxmin, separating or fan\n");
                return 2;
            }
            rules = {*r};
        } else if (a == "--lattice" && i + 1 < argc) {
            const std::optional<LatticeMetric> l = value_of(lattice_metric_names, argv[++i]);
            if (!l) {
                std::fprintf(stderr, "warpmesh prove: --lattice expects square or rhombic\n");
                return 2;
            }
            metric = *l;
        } else if (a == "--keys" && i + 1 < argc) {  // indices into prover::consistent_keys()
            use_subset = sign_subset = true;
            const long n = static_cast<long>(prover::consistent_keys().size());
            std::string bad;
            if (!prover::parse_key_list(argv[++i], n, subset, bad)) {
                std::fprintf(stderr, "warpmesh prove: --keys expects key indices 0..%ld separated by commas (bad: '%s')\n", n - 1, bad.c_str());
                return 2;
            }
        } else if (a == "--junction-keys" && i + 1 < argc) {  // indices into prover::junction_keys(), or "all"
            use_subset = junction_subset = true;
            const long n = static_cast<long>(prover::junction_keys().size());
            std::string bad;
            if (std::string(argv[i + 1]) == "all") {
                for (int k = 0; k < n; ++k) jsubset.push_back(k);
                ++i;
            } else if (!prover::parse_key_list(argv[++i], n, jsubset, bad)) {
                std::fprintf(stderr, "warpmesh prove: --junction-keys expects all or key indices 0..%ld separated by commas (bad: '%s')\n", n - 1,
                             bad.c_str());
                return 2;
            }
        } else {
            std::fprintf(stderr, "usage: warpmesh prove [--out DIR] [--threads N] [--lattice square|rhombic] [--rule R] [--keys I,J,...] [--junction-keys I,J,...]\n");
            return 2;
        }
    }
    // The rhombic metric: the two diagonal rules over the sign keys (the
    // rhombic mesher is uniform, one region: no junction keys; the fan rule's
    // threshold is a square-lattice cotangent, not defined there).
    const bool rhombic = metric == LatticeMetric::rhombic;
    if (rhombic && (junction_subset || (rules.size() == 1 && rules[0] == DiagonalRule::fan))) {
        std::fprintf(stderr, "warpmesh prove: --lattice rhombic proves the maxmin and separating rules on the sign keys only\n");
        return 2;
    }
    const std::string prefix = rhombic ? "rhombic_" : "";
    std::filesystem::create_directories(out);
    int status = 0;
    bool first = true;  // the first run truncates key_table.txt
    // The two diagonal rules over the sign keys, then the separating rule over
    // the junction keys (multi-material squares with 3 or 4 materials; the
    // max-min rule is refused with materials), then the fan rule over the sign
    // keys and over the junction keys: maxmin.cert, separating.cert,
    // materials.cert, fan.cert, materials_fan.cert.
    struct Run {
        DiagonalRule rule;
        prover::KeySpace space;
        const char* file;
    };
    for (const Run run : {Run{DiagonalRule::maxmin, prover::KeySpace::signs, "maxmin"},
                          Run{DiagonalRule::separating, prover::KeySpace::signs, "separating"},
                          Run{DiagonalRule::separating, prover::KeySpace::junctions, "materials"},
                          Run{DiagonalRule::fan, prover::KeySpace::signs, "fan"},
                          Run{DiagonalRule::fan, prover::KeySpace::junctions, "materials_fan"}}) {
        const DiagonalRule r = run.rule;
        // With --rule only that rule's runs.
        if (std::find(rules.begin(), rules.end(), r) == rules.end()) continue;
        // With --keys / --junction-keys only the runs asked for (a test's subset).
        if (use_subset && !(run.space == prover::KeySpace::junctions ? junction_subset : sign_subset)) continue;
        if (rhombic && (run.space == prover::KeySpace::junctions || r == DiagonalRule::fan)) continue;
        std::string log;
        const std::vector<int>* ids = run.space == prover::KeySpace::junctions ? (use_subset ? &jsubset : nullptr)
                                                                               : (use_subset ? &subset : nullptr);
        const std::string cert = prover::run_proof(r, ids, &log, run.space, metric);
        const std::string name = prover::rule_name(r);
        const std::string path = out + "/" + prefix + run.file + ".cert";
        std::ofstream f(path + ".tmp", std::ios::binary);
        f << cert;
        f.close();
        std::filesystem::rename(path + ".tmp", path);
        // The key table (square lattice): one line per key.
        if (!rhombic) write_key_table(out + "/key_table.txt", name, cert, std::exchange(first, false));
        std::fputs(log.c_str(), stdout);
        std::fflush(stdout);
        // Exit 1: a key not proved (the certificate is incomplete; the checker
        // rejects it).  Exit 3: a category has an inverted configuration — the
        // certificate states a counter-example, not a bound (the checker's 3).
        if (log.find("FAILED") != std::string::npos) status = 1;
        else if (status == 0 && log.find("orientation FAILS") != std::string::npos) status = 3;
    }
    return status;
}

}  // namespace warpmesh
