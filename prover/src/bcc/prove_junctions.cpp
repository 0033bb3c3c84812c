// prove_junctions.cpp — `warpmesh-prove-bcc --junctions`: the junction keys'
// certificate proofs/bcc_junctions.cert (format: proofs/README.md,
// "Junction keys (3D, bcc_junctions.cert)").  Each key is proved face by
// face (junction_subject: a face's cone tetrahedra over the parameters they
// depend on), all four against one claim, the key's, made from the most
// extreme of its faces' witnesses (prove_tight); the theorem is the
// extremes of the keys' claims.  Every key is proved independently and the
// lines are written in key order: the certificate is the same for any
// thread count.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "warpmesh/key_progress.hpp"
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

double degrees(double cos2, bool obtuse) {  // messages only
    const double a = std::acos(std::sqrt(cos2)) * 180 / M_PI;
    return obtuse ? 180 - a : a;
}
Claim extremes_of(const Claim& a, const Claim& b) {
    return {std::max(a.cmin, b.cmin), std::max(a.cmax, b.cmax), std::max(a.cface, b.cface)};
}

// `--junctions --extremes`: the witness search alone over every face of every
// key (not on the proof path): the smallest and largest dihedral angle found
// and where ("CODE face F").
int print_junction_extremes(const std::vector<JunctionKey>& keys, const bcc::Alphas& al) {
    const long n = 4 * static_cast<long>(keys.size());
    std::vector<Witness> lo(static_cast<std::size_t>(n)), hi(static_cast<std::size_t>(n));
    {
        prover::KeyProgress progress("warpmesh-prove-bcc: searching junction faces", n);
#pragma omp parallel for schedule(dynamic, 1)
        for (long i = 0; i < n; ++i) {
            const Subject s = junction_subject(keys[static_cast<std::size_t>(i / 4)], static_cast<int>(i % 4), al);
            lo[static_cast<std::size_t>(i)] = search_subject(s, 1), hi[static_cast<std::size_t>(i)] = search_subject(s, -1);
            progress.tick();
        }
    }
    std::size_t a = 0, b = 0;
    for (std::size_t i = 0; i < lo.size(); ++i) {
        if (lo[i].cos > lo[a].cos) a = i;
        if (hi[i].cos < hi[b].cos) b = i;
    }
    const auto deg = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI; };
    std::printf("extremes %.10f %s face %zu %.10f %s face %zu\n", deg(lo[a].cos), bcc::code_of(keys[a / 4]).c_str(), a % 4,
                deg(hi[b].cos), bcc::code_of(keys[b / 4]).c_str(), b % 4);
    return 0;
}

}  // namespace

int prove_junctions(const std::vector<JunctionKey>& keys, const bcc::Alphas& al, const Margins& mg, bool extremes,
                    const std::string& out) {
    if (extremes) return print_junction_extremes(keys, al);
    const long n = static_cast<long>(keys.size());
    std::vector<KeyProof> proofs(4 * keys.size());
    const auto t0 = std::chrono::steady_clock::now();
    {
        prover::KeyProgress progress("warpmesh-prove-bcc: proving junction keys", n);
#pragma omp parallel for schedule(dynamic, 1)
        for (long i = 0; i < n; ++i) {
            std::vector<Subject> faces;
            for (int f = 0; f < 4; ++f) faces.push_back(junction_subject(keys[static_cast<std::size_t>(i)], f, al));
            const std::vector<KeyProof> p = prove_tight(faces, mg);
            std::copy(p.begin(), p.end(), proofs.begin() + 4 * i);
            progress.tick();
        }
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    long leaves = 0;
    int failed = 0;
    Claim theorem{0, 0, 0};
    std::ostringstream lines;
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const Claim key = proofs[4 * k].claim;  // the same for its four faces (prove_tight)
        std::ostringstream faces;
        for (std::size_t f = 0; f < 4; ++f) {
            const KeyProof& p = proofs[4 * k + f];
            leaves += p.leaves;
            if (!p.ok) {
                ++failed;
                std::fprintf(stderr, "junction key %s face %zu: not proved (%s) near", bcc::code_of(keys[k]).c_str(), f,
                             p.fail_kind == 0 ? "orientation" : p.fail_kind == 1 ? "minimum" : p.fail_kind == 2 ? "maximum" : "face angle");
                for (int j = 0; j < p.root.m; ++j) std::fprintf(stderr, " %.6f", p.fail_point[static_cast<std::size_t>(j)]);
                std::fprintf(stderr, "\n");
                break;  // the key's later faces were not tried
            }
            faces << "face " << f << " " << proof_fields(p, false) << "\n";
        }
        theorem = extremes_of(theorem, key);
        lines << "key " << bcc::code_of(keys[k]) << " " << dyadic40(key.cmin) << " " << dyadic40(key.cmax) << " " << dyadic40(key.cface)
              << "\n"
              << faces.str();
    }
    std::fprintf(stderr, "warpmesh-prove-bcc: junction keys at alphas %lld/%lld %lld/%lld, claim [%.4f, %.4f] deg, face angles >= %.4f deg: "
                 "%zu keys, %d faces not proved, %ld leaves, %.1f s\n",
                 static_cast<long long>(al.long_num), static_cast<long long>(al.long_den), static_cast<long long>(al.short_num),
                 static_cast<long long>(al.short_den), degrees(theorem.cmin, false), degrees(theorem.cmax, true), degrees(theorem.cface, false),
                 keys.size(), failed, leaves, secs);
    if (failed) return 1;
    std::ofstream f(out, std::ios::binary);
    f << "warpmesh-bcc-junctions 1\n# Dihedral angle bounds for the junction keys of the BCC generic tetrahedron.  Format: proofs/README.md.\n"
      << "alphas " << al.long_num << "/" << al.long_den << " " << al.short_num << "/" << al.short_den << "\n"
      << "claim " << dyadic40(theorem.cmin) << " " << dyadic40(theorem.cmax) << " " << dyadic40(theorem.cface) << "\n"
      << "keys " << keys.size() << "\n"
      << lines.str();
    if (!f) {
        std::fprintf(stderr, "warpmesh-prove-bcc: cannot write %s\n", out.c_str());
        return 1;
    }
    return 0;
}

}  // namespace warpmesh::bcc_prover
