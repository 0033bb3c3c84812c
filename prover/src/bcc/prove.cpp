// prove.cpp — `warpmesh-prove-bcc`: runs the branch and bound over every key
// and writes the certificate (format: proofs/README.md, "The BCC
// certificate").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "warpmesh/key_list.hpp"
#include "warpmesh/key_progress.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

// `--extremes`: the prover's own witness search (targets.cpp, the same
// deterministic search that chooses each key's claim) over every key, no
// proof: prints the smallest and largest angle found and their keys, from
// which scripts/bcc-frontier.sh chooses a pair's caps, then how many keys'
// largest angle found is acute, and the key with the smallest largest angle
// and that angle (if acute, that key's max claim, which is at least 90°,
// is more than 0.1° from its witness: loose).  Not on the proof path (acos
// only names the angles).
int print_extremes(const std::vector<Key>& keys, const bcc::Alphas& al, FaceRule rule) {
    std::vector<Witness> lo(keys.size()), hi(keys.size());
    {
        prover::KeyProgress progress("warpmesh-prove-bcc: searching", static_cast<long>(keys.size()));
#pragma omp parallel for schedule(dynamic, 4)
        for (long i = 0; i < static_cast<long>(keys.size()); ++i) {
            const auto ps = key_params(keys[static_cast<std::size_t>(i)], al);
            lo[static_cast<std::size_t>(i)] = search_witness(keys[static_cast<std::size_t>(i)], ps, 1, nullptr, rule);
            hi[static_cast<std::size_t>(i)] = search_witness(keys[static_cast<std::size_t>(i)], ps, -1, nullptr, rule);
            progress.tick();
        }
    }
    std::size_t a = 0, b = 0, c = 0;  // the most extreme witnesses (largest cos, smallest cos); c: largest max cos
    int acute = 0;                     // keys whose largest angle found is acute
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (lo[i].cos > lo[a].cos) a = i;
        if (hi[i].cos < hi[b].cos) b = i;
        if (hi[i].cos > hi[c].cos) c = i;
        acute += hi[i].cos > 0;
    }
    const auto deg = [](double x) { return std::acos(std::clamp(x, -1.0, 1.0)) * 180 / M_PI; };
    std::printf("extremes %.10f %s %.10f %s %d %s %.10f\n", deg(lo[a].cos), code_of(keys[a]).c_str(), deg(hi[b].cos),
                code_of(keys[b]).c_str(), acute, code_of(keys[c]).c_str(), deg(hi[c].cos));
    return 0;
}

}  // namespace

int prove_bcc_main(int argc, char** argv) {
    std::string la = "0.285", sa = "0.3985";  // bcc::parity_alphas
    std::optional<std::string> out;
    double cap_min = default_cap_min_deg, cap_max = default_cap_max_deg;
    std::optional<std::string> key_list;  // --keys, parsed against the enumeration below
    bool extremes = false, junctions = false, graded = false;
    FaceRule rule = FaceRule::parity;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--out" && more) out = argv[++i];
        else if (a == "--alphas" && i + 2 < argc) la = argv[++i], sa = argv[++i];
        else if (a == "--extremes") extremes = true;
        else if (a == "--junctions") junctions = true;
        else if (a == "--graded") graded = true;
        else if (a == "--face-rule" && more && parse_face_rule(argv[i + 1])) rule = *parse_face_rule(argv[++i]);
        else if (a == "--cap-min-deg" && more) cap_min = std::atof(argv[++i]);
        else if (a == "--cap-max-deg" && more) cap_max = std::atof(argv[++i]);
        else if (a == "--threads" && more) {
            prover::set_threads(argv[++i]);
        } else if (a == "--keys" && more) {
            key_list = argv[++i];
        } else {
            std::fprintf(stderr, "usage: warpmesh-prove-bcc [--out FILE] [--alphas L S] [--cap-min-deg D] [--cap-max-deg D] [--threads N] [--keys I,J,..] [--extremes] [--face-rule parity|delaunay] [--junctions] [--graded]\n");
            return 2;
        }
    }
    // --graded: the templates need no alphas (no vertex of theirs is warped).
    if (graded) return prove_graded(out.value_or("proofs/bcc_graded.cert"));
    bcc::Alphas al{0, 100000, 0, 100000};
    if (!parse_alpha(la, al.long_num) || !parse_alpha(sa, al.short_num) || !(cap_min > 0 && cap_min < 90) ||
        !(cap_max > 90 && cap_max < 180)) {
        std::fprintf(stderr, "warpmesh-prove-bcc: alphas must be decimals in (0, 0.5) with at most 5 digits, 0 < cap-min-deg < 90 < cap-max-deg < 180\n");
        return 2;
    }
    if (junctions && rule != FaceRule::parity) {
        std::fprintf(stderr, "warpmesh-prove-bcc: --junctions proves the parity face rule's junctions (multi-material meshes use it)\n");
        return 2;
    }
    // --junctions: the junction keys, numbered in canonical order as --keys reads them.
    const std::vector<Key> all = junctions ? std::vector<Key>{} : enumerate_keys();
    const std::size_t nkeys = junctions ? enumerate_junction_keys().size() : all.size();
    std::vector<int> subset;
    std::string bad;
    if (key_list && !prover::parse_key_list(*key_list, static_cast<long>(nkeys), subset, bad)) {
        std::fprintf(stderr, "warpmesh-prove-bcc: --keys expects key indices 0..%zu separated by commas (bad: '%s')\n", nkeys - 1,
                     bad.c_str());
        return 2;
    }
    Margins mg;
    mg.cap = cap_claim(cap_min, cap_max);
    if (junctions) {
        const std::vector<JunctionKey> jall = enumerate_junction_keys();
        std::vector<JunctionKey> jkeys;
        if (subset.empty()) jkeys = jall;
        else
            for (int k : subset) jkeys.push_back(jall[static_cast<std::size_t>(k)]);
        return prove_junctions(jkeys, al, mg, extremes, out.value_or("proofs/bcc_junctions.cert"));
    }
    std::vector<Key> keys;
    if (subset.empty()) keys = all;
    else
        for (int k : subset) keys.push_back(all[static_cast<std::size_t>(k)]);  // in range: parse_key_list
    if (extremes) return print_extremes(keys, al, rule);
    std::vector<KeyProof> proofs(keys.size());
    const auto t0 = std::chrono::steady_clock::now();
    {
        prover::KeyProgress progress("warpmesh-prove-bcc: proving", static_cast<long>(keys.size()));
#pragma omp parallel for schedule(dynamic, 4)
        for (long i = 0; i < static_cast<long>(keys.size()); ++i) {
            proofs[static_cast<std::size_t>(i)] = prove_key_tight(keys[static_cast<std::size_t>(i)], al, mg, default_max_depth, rule);
            progress.tick();
        }
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    long leaves = 0;
    int failed = 0;
    Claim claim{0, 0, 0};  // the theorem: the extremes of the keys' claims
    std::ostringstream lines;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const KeyProof& p = proofs[i];
        leaves += p.leaves;
        if (!p.ok) {
            ++failed;
            std::fprintf(stderr, "key %s: not proved (%s) near", code_of(keys[i]).c_str(),
                         p.fail_kind == 0 ? "orientation" : p.fail_kind == 1 ? "minimum" : p.fail_kind == 2 ? "maximum" : "face angle");
            for (int j = 0; j < p.root.m; ++j) std::fprintf(stderr, " %.6f", p.fail_point[static_cast<std::size_t>(j)]);
            std::fprintf(stderr, "\n");
            continue;
        }
        claim.cmin = std::max(claim.cmin, p.claim.cmin), claim.cmax = std::max(claim.cmax, p.claim.cmax);
        claim.cface = std::max(claim.cface, p.claim.cface);
        lines << certificate_line(keys[i], p) << "\n";
    }
    std::ostringstream cert;
    // Format 5 is format 4 with the face-rule line; the parity rule's stays format 4.
    cert << "warpmesh-bcc-certificate " << (rule == FaceRule::delaunay ? 5 : 4)
         << "\n# Dihedral angle bounds for the BCC generic tetrahedron.  Format: proofs/README.md.\n";
    if (rule == FaceRule::delaunay) cert << "face-rule delaunay\n";
    cert << "alphas " << al.long_num << "/100000 " << al.short_num << "/100000\n";
    cert << "claim " << dyadic40(claim.cmin) << " " << dyadic40(claim.cmax) << " " << dyadic40(claim.cface) << "\n";
    cert << "keys " << keys.size() << "\n" << lines.str();
    std::fprintf(stderr, "warpmesh-prove-bcc: %salphas %s %s, claim [%.4f, %.4f] deg, face angles >= %.4f deg: %zu keys, %d not proved, %ld leaves, %.1f s\n",
                 rule == FaceRule::delaunay ? "face rule delaunay, " : "", la.c_str(), sa.c_str(), std::acos(std::sqrt(claim.cmin)) * 180 / M_PI,
                 180 - std::acos(std::sqrt(claim.cmax)) * 180 / M_PI, std::acos(std::sqrt(claim.cface)) * 180 / M_PI,
                 keys.size(), failed, leaves, secs);
    if (failed) return 1;
    const std::string path = out.value_or("proofs/bcc.cert");
    std::ofstream f(path, std::ios::binary);
    f << cert.str();
    if (!f) {
        std::fprintf(stderr, "warpmesh-prove-bcc: cannot write %s\n", path.c_str());
        return 1;
    }
    return 0;
}

}  // namespace warpmesh::bcc_prover

int main(int argc, char** argv) { return warpmesh::bcc_prover::prove_bcc_main(argc, argv); }
