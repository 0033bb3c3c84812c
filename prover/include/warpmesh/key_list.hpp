// The provers' command-line arguments shared by their tools: --keys lists of
// key indices, and --threads.
//
// Contract: parse_key_list reads "I,J,..." — decimal integers, each in
// [0, count), the number of keys of the space the indices refer to — and
// appends them to `out` in order.  It returns false, with the offending token
// (or "" for an empty list) in `bad`, if any token is empty, not a decimal
// integer, or out of range; `out` is then unspecified.  The tools report that
// and exit with status 2 instead of proving a list nobody asked for.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh::prover {

// --threads N: OpenMP's thread count, at least 1 (ignored without OpenMP).
inline void set_threads(const char* n) {
#ifdef _OPENMP
    omp_set_num_threads(std::max(1, std::atoi(n)));
#else
    (void)n;
#endif
}

inline bool parse_key_index(const std::string& tok, long count, int& k) {
    if (tok.empty() || tok.size() > 9) return false;
    for (const char c : tok)
        if (c < '0' || c > '9') return false;
    const long v = std::strtol(tok.c_str(), nullptr, 10);
    if (v >= count) return false;
    k = static_cast<int>(v);
    return true;
}

inline bool parse_key_list(const std::string& text, long count, std::vector<int>& out, std::string& bad) {
    bad.clear();
    if (text.empty()) return false;
    std::stringstream ss(text);
    int n = 0;
    for (std::string tok; std::getline(ss, tok, ',');) {
        int k = 0;
        if (!parse_key_index(tok, count, k)) {
            bad = tok;
            return false;
        }
        out.push_back(k), ++n;
    }
    if (text.back() == ',') return false;  // a trailing empty token
    return n > 0;
}

}  // namespace warpmesh::prover
