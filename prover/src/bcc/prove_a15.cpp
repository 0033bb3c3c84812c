// prove_a15.cpp — `warpmesh-prove-a15` (issue 51): the 3D prover's branch
// and bound and witness search over the A15 keys (generic_a15_keys.hpp),
// through a15_subject.  Prints the extremes found (--extremes) or proves
// every key (or every N-th, --every, or those listed, --keys) tight against
// the caps, reports the theorem the proved claims give and, if every key is
// proved, writes the certificate (--out; proofs/README.md, "The A15
// certificate"), which `warpmesh-check-bcc` checks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "warpmesh/key_list.hpp"
#include "warpmesh/key_progress.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

// "0.285" -> 28500 / 100000 (parse_alpha, keys.cpp).
bool parse_alpha(const std::string& s, a15::Fraction& f) {
    std::int64_t num = 0;
    if (!bcc_prover::parse_alpha(s, num)) return false;
    f = {num, 100000};
    return true;
}
double deg(double c) { return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI; }
// The angle a claim's cos² names (acute side for cmin, obtuse for cmax).
double claim_deg(double c2, bool obtuse) { return obtuse ? 180 - deg(std::sqrt(c2)) : deg(std::sqrt(c2)); }

struct Run {
    std::vector<a15::Key> keys;
    a15::Alphas al;
    Margins mg;
    bool extremes = false;
    std::optional<std::string> out;
};

int run(const Run& r) {
    const std::size_t n = r.keys.size();
    std::vector<Witness> lo(n), hi(n);
    std::vector<KeyProof> proofs(n);
    {
        prover::KeyProgress progress(r.extremes ? "warpmesh-prove-a15: searching" : "warpmesh-prove-a15: proving", static_cast<long>(n));
#pragma omp parallel for schedule(dynamic, 4)
        for (long i = 0; i < static_cast<long>(n); ++i) {
            const auto I = static_cast<std::size_t>(i);
            const Subject s = a15_subject(r.keys[I], r.al);
            if (r.extremes) {
                lo[I] = search_subject(s, 1), hi[I] = search_subject(s, -1);
            } else {
                proofs[I] = prove_subject_tight(s, r.mg);
                lo[I] = proofs[I].wmin, hi[I] = proofs[I].wmax;
            }
            progress.tick();
        }
    }
    for (std::size_t i = 0; i < n && !r.extremes; ++i)  // kind: 0 orientation, 1 minimum, 2 maximum, 3 budget, 4 face angle
        if (!proofs[i].ok) std::fprintf(stderr, "key %s: not proved (kind %d)\n", a15::code_of(r.keys[i]).c_str(), proofs[i].fail_kind);
    std::size_t a = 0, b = 0, ca = 0, cb = 0;
    int failed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (lo[i].cos > lo[a].cos) a = i;
        if (hi[i].cos < hi[b].cos) b = i;
        if (r.extremes) continue;
        failed += !proofs[i].ok;
        if (proofs[i].claim.cmin > proofs[ca].claim.cmin) ca = i;
        if (proofs[i].claim.cmax > proofs[cb].claim.cmax) cb = i;
    }
    std::printf("keys %zu\nwitness-min %.10f %s\nwitness-max %.10f %s\n", n, deg(lo[a].cos), a15::code_of(r.keys[a]).c_str(),
                deg(hi[b].cos), a15::code_of(r.keys[b]).c_str());
    if (r.extremes) return 0;
    std::printf("proved %zu failed %d\nclaim-min %.6f %s\nclaim-max %.6f %s\n", n - static_cast<std::size_t>(failed), failed,
                claim_deg(proofs[ca].claim.cmin, false), a15::code_of(r.keys[ca]).c_str(), claim_deg(proofs[cb].claim.cmax, true),
                a15::code_of(r.keys[cb]).c_str());
    if (failed || !r.out) return failed == 0 ? 0 : 1;
    Claim claim{0, 0, 0};  // the theorem: the extremes of the keys' claims
    for (const KeyProof& p : proofs)
        claim = {std::max(claim.cmin, p.claim.cmin), std::max(claim.cmax, p.claim.cmax), std::max(claim.cface, p.claim.cface)};
    std::ofstream o(*r.out, std::ios::binary);
    const auto q = [](const a15::Fraction& f) { return std::to_string(f.num) + "/" + std::to_string(f.den); };
    o << "warpmesh-a15-certificate 1\n# Dihedral angle bounds for the A15 generic tetrahedron.  Format: proofs/README.md.\n"
      << "alphas " << q(r.al.chain) << " " << q(r.al.wide) << " " << q(r.al.mixed_at_a) << " " << q(r.al.mixed_at_b) << "\n"
      << "claim " << dyadic40(claim.cmin) << " " << dyadic40(claim.cmax) << " " << dyadic40(claim.cface) << "\n"
      << "keys " << n << "\n";
    for (std::size_t i = 0; i < n; ++i) {
        const Subject s = a15_subject(r.keys[i], r.al);
        o << "key " << a15::code_of(r.keys[i]) << " " << proof_fields(proofs[i], true, &s) << "\n";
    }
    if (!o) {
        std::fprintf(stderr, "warpmesh-prove-a15: cannot write %s\n", r.out->c_str());
        return 1;
    }
    return 0;
}

}  // namespace
}  // namespace warpmesh::bcc_prover

int main(int argc, char** argv) {
    using namespace warpmesh::bcc_prover;
    std::array<std::string, 4> alpha{"0.3", "0.3", "0.3", "0.3"};
    double cap_min = 12.0, cap_max = 160.0, cap_face = 0;
    long every = 1;
    std::optional<std::string> key_list;
    Run r;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--alphas" && i + 4 < argc)
            for (auto& s : alpha) s = argv[++i];
        else if (a == "--cap-min-deg" && more) cap_min = std::atof(argv[++i]);
        else if (a == "--cap-max-deg" && more) cap_max = std::atof(argv[++i]);
        else if (a == "--cap-face-deg" && more) cap_face = std::atof(argv[++i]);
        else if (a == "--every" && more) every = std::atol(argv[++i]);
        else if (a == "--keys" && more) key_list = argv[++i];
        else if (a == "--extremes") r.extremes = true;
        else if (a == "--out" && more) r.out = argv[++i];
        else if (a == "--threads" && more) {
            warpmesh::prover::set_threads(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: warpmesh-prove-a15 [--alphas CHAIN WIDE MIXED_AT_A MIXED_AT_B] [--cap-min-deg D] [--cap-max-deg D] [--cap-face-deg D] [--every N | --keys I,J,..] [--extremes] [--out FILE] [--threads N]\n");
            return 2;
        }
    }
    if (!parse_alpha(alpha[0], r.al.chain) || !parse_alpha(alpha[1], r.al.wide) || !parse_alpha(alpha[2], r.al.mixed_at_a) ||
        !parse_alpha(alpha[3], r.al.mixed_at_b) || !(cap_min > 0 && cap_min < 90) || !(cap_max > 90 && cap_max < 180) || !(cap_face >= 0 && cap_face < 60) || every < 1) {
        std::fprintf(stderr, "warpmesh-prove-a15: alphas must be decimals in (0, 0.5) with at most 5 digits, 0 < cap-min-deg < 90 < cap-max-deg < 180, 0 <= cap-face-deg < 60, every >= 1\n");
        return 2;
    }
    // The face-angle cap: by default none; a key whose tight face-angle
    // claim is not proved within the budget claims the cap.
    r.mg.cap = cap_claim(cap_min, cap_max, cap_face);
    const auto all = warpmesh::a15::enumerate_keys();
    std::vector<int> subset;
    std::string bad;
    if (key_list && !warpmesh::prover::parse_key_list(*key_list, static_cast<long>(all.size()), subset, bad)) {
        std::fprintf(stderr, "warpmesh-prove-a15: --keys expects key indices 0..%zu separated by commas (bad: '%s')\n", all.size() - 1, bad.c_str());
        return 2;
    }
    for (int k : subset) r.keys.push_back(all[static_cast<std::size_t>(k)]);
    for (std::size_t i = 0; i < all.size() && !key_list; i += static_cast<std::size_t>(every)) r.keys.push_back(all[i]);
    return run(r);
}
