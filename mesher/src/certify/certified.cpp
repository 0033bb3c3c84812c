// certified.cpp — the compiled-in per-key bounds (certified.hpp) and the
// certification of a mesh: per-triangle bound, flatness, verification.
#include "warpmesh/certify/certified.hpp"

#include "warpmesh/mesh2d/lattice.hpp"  // SquareKeys, Lattice, Mesh, LevelSet

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace warpmesh {

namespace generated {
extern const std::string_view certified_maxmin_keys;
extern const std::string_view certified_separating_keys;
extern const std::string_view certified_materials_keys;
extern const std::string_view certified_materials_fan_keys;
extern const std::string_view certified_fan_keys;
extern const std::string_view certified_rhombic_maxmin_keys;
extern const std::string_view certified_rhombic_separating_keys;
}  // namespace generated

namespace {

constexpr double pi = 3.14159265358979323846;
double arccot_deg(double c) { return std::atan2(1.0, c) * 180.0 / pi; }
// The physical angle of a bound on the metric's ratio dot / cross: cot on the
// square lattice, r = sqrt(3) cot on the rhombic one (reporting only).
double angle_deg(double r, LatticeMetric metric) {
    return metric == LatticeMetric::rhombic ? std::atan2(std::sqrt(3.0), r) * 180.0 / pi : arccot_deg(r);
}

int sign_index(int s) { return s + 1; }
int char_sign(char c) { return c == '-' ? -1 : c == '0' ? 0 : c == '+' ? 1 : 9; }
int char_warp(char c) {
    switch (c) {
        case 's': return 0;
        case 'R': return 1;
        case 'L': return 2;
        case 'U': return 3;
        case 'D': return 4;
        default: return 9;
    }
}

constexpr int raw_keys = 15 * 15 * 15 * 15;
int raw_index(const std::array<CornerState, 4>& cs) {
    int k = 0;
    for (int c = 0; c < 4; ++c)
        k = k * 15 + sign_index(cs[static_cast<std::size_t>(c)].sign) * 5 + static_cast<int>(cs[static_cast<std::size_t>(c)].warp);
    return k;
}

// A compiled-in key table over `raw` raw key indices (sign keys: raw_index;
// junction keys: raw_junction_index).
template <int raw>
struct KeyTable {
    std::vector<CertifiedBound> bound = std::vector<CertifiedBound>(raw);
    std::vector<std::uint8_t> known = std::vector<std::uint8_t>(raw, 0);
    std::size_t count = 0;
    CertifiedTheorem theorem{};
};
using Table = KeyTable<raw_keys>;

Table build(std::string_view text, LatticeMetric metric = LatticeMetric::square) {
    Table t;
    double max_any = -std::numeric_limits<double>::infinity(), max_flat = max_any;
    double min_any = std::numeric_limits<double>::infinity(), min_flat = min_any;  // least cot: largest angle
    for (const CertKeyLine& k : parse_cert_key_lines(text)) {
        if (k.code.size() != 8) throw std::runtime_error("certified table: bad key code " + k.code);
        std::array<CornerState, 4> cs{};
        for (int c = 0; c < 4; ++c) {
            const int s = char_sign(k.code[static_cast<std::size_t>(2 * c)]);
            const int w = char_warp(k.code[static_cast<std::size_t>(2 * c + 1)]);
            if (s == 9 || w == 9) throw std::runtime_error("certified table: bad key code " + k.code);
            cs[static_cast<std::size_t>(c)] = {static_cast<std::int8_t>(s), static_cast<Warp>(w)};
        }
        const double qmin = parse_rational(k.qmin), qmax = parse_rational(k.qmax);
        const int idx = raw_index(cs);
        t.bound[static_cast<std::size_t>(idx)] = {angle_deg(qmin, metric), angle_deg(qmax, metric), qmax, qmin, k.flat};
        t.known[static_cast<std::size_t>(idx)] = 1;
        ++t.count;
        max_any = std::max(max_any, qmin);
        min_any = std::min(min_any, qmax);
        if (k.flat) max_flat = std::max(max_flat, qmin), min_flat = std::min(min_flat, qmax);
    }
    t.theorem = {angle_deg(max_any, metric), angle_deg(max_flat, metric), max_any, max_flat, angle_deg(min_any, metric),
                 angle_deg(min_flat, metric)};
    return t;
}

// Junction keys: a corner's state is letter * 5 + warp (20 states), corner A
// most significant (the prover's canonical order).
constexpr int raw_junction_keys = 20 * 20 * 20 * 20;
int raw_junction_index(const std::array<MaterialCorner, 4>& cs) {
    int k = 0;
    for (const MaterialCorner& c : cs) k = k * 20 + c.material * 5 + static_cast<int>(c.warp);
    return k;
}

using JunctionTable = KeyTable<raw_junction_keys>;

JunctionTable build_junctions(std::string_view text) {
    JunctionTable t;
    double max_any = -std::numeric_limits<double>::infinity(), min_any = std::numeric_limits<double>::infinity();
    for (const CertKeyLine& k : parse_cert_key_lines(text)) {
        std::array<MaterialCorner, 4> cs{};
        bool ok = k.code.size() == 8 && !k.flat;
        for (std::size_t c = 0; c < 4 && ok; ++c) {
            const char l = k.code[2 * c];
            const int w = char_warp(k.code[2 * c + 1]);
            ok = l >= 'a' && l <= 'd' && w != 9;
            if (ok) cs[c] = {static_cast<std::uint16_t>(l - 'a'), static_cast<Warp>(w)};
        }
        if (!ok || junction_letters(cs)[0].material != 0 || junction_key_code(junction_letters(cs)) != k.code)
            throw std::runtime_error("certified table: bad junction key code " + k.code);
        const double qmin = parse_rational(k.qmin), qmax = parse_rational(k.qmax);
        const int idx = raw_junction_index(cs);
        t.bound[static_cast<std::size_t>(idx)] = {arccot_deg(qmin), arccot_deg(qmax), qmax, qmin, false};
        t.known[static_cast<std::size_t>(idx)] = 1;
        ++t.count;
        max_any = std::max(max_any, qmin);
        min_any = std::min(min_any, qmax);
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    t.theorem = {arccot_deg(max_any), nan, max_any, nan, arccot_deg(min_any), nan};
    return t;
}

const JunctionTable& junction_table(DiagonalRule rule) {
    static const JunctionTable separating = build_junctions(generated::certified_materials_keys);
    static const JunctionTable fan = build_junctions(generated::certified_materials_fan_keys);
    static const JunctionTable none;
    return rule == DiagonalRule::separating ? separating : rule == DiagonalRule::fan ? fan : none;
}

const Table& table(DiagonalRule rule, LatticeMetric metric) {
    static const Table maxmin = build(generated::certified_maxmin_keys);
    static const Table separating = build(generated::certified_separating_keys);
    static const Table fan = build(generated::certified_fan_keys);
    static const Table rhombic_maxmin = build(generated::certified_rhombic_maxmin_keys, LatticeMetric::rhombic);
    static const Table rhombic_separating = build(generated::certified_rhombic_separating_keys, LatticeMetric::rhombic);
    static const Table none;
    if (metric == LatticeMetric::rhombic)
        return rule == DiagonalRule::maxmin ? rhombic_maxmin : rule == DiagonalRule::separating ? rhombic_separating : none;
    return rule == DiagonalRule::maxmin ? maxmin : rule == DiagonalRule::separating ? separating : fan;
}

}  // namespace

std::string_view certified_table_text(DiagonalRule rule, LatticeMetric metric) {
    if (metric == LatticeMetric::rhombic)
        return rule == DiagonalRule::maxmin       ? generated::certified_rhombic_maxmin_keys
               : rule == DiagonalRule::separating ? generated::certified_rhombic_separating_keys
                                                  : std::string_view{};
    return rule == DiagonalRule::maxmin       ? generated::certified_maxmin_keys
           : rule == DiagonalRule::separating ? generated::certified_separating_keys
                                              : generated::certified_fan_keys;
}

std::string_view certified_junction_table_text(DiagonalRule rule) {
    return rule == DiagonalRule::separating ? generated::certified_materials_keys
           : rule == DiagonalRule::fan      ? generated::certified_materials_fan_keys
                                            : std::string_view{};
}

const CertifiedBound* certified_junction_bound(const std::array<MaterialCorner, 4>& letters, DiagonalRule rule) {
    for (const auto& c : letters)
        if (c.material > 3 || static_cast<int>(c.warp) >= warp_count) return nullptr;
    const JunctionTable& t = junction_table(rule);
    const int idx = raw_junction_index(letters);
    return t.known[static_cast<std::size_t>(idx)] ? &t.bound[static_cast<std::size_t>(idx)] : nullptr;
}
std::size_t certified_junction_key_count(DiagonalRule rule) { return junction_table(rule).count; }
CertifiedTheorem certified_junction_theorem(DiagonalRule rule) { return junction_table(rule).theorem; }

double parse_rational(std::string_view text) {
    auto parse_int = [&](std::string_view s) -> __int128 {
        if (s.empty()) throw std::runtime_error("bad rational '" + std::string(text) + "'");
        bool neg = s[0] == '-';
        if (neg || s[0] == '+') s.remove_prefix(1);
        if (s.empty() || s.size() > 36) throw std::runtime_error("bad rational '" + std::string(text) + "'");
        __int128 v = 0;
        for (char c : s) {
            if (c < '0' || c > '9') throw std::runtime_error("bad rational '" + std::string(text) + "'");
            v = v * 10 + (c - '0');
        }
        return neg ? -v : v;
    };
    const auto slash = text.find('/');
    if (slash == std::string_view::npos) return static_cast<double>(static_cast<long double>(parse_int(text)));
    const __int128 p = parse_int(text.substr(0, slash)), q = parse_int(text.substr(slash + 1));
    if (q <= 0) throw std::runtime_error("bad rational '" + std::string(text) + "'");
    // Both below 2^53 (every key bound): exact as doubles, so one IEEE division
    // gives the correctly rounded quotient.  Larger ones (witness values) go
    // through long double, a few ulps off — the table needs no better.
    constexpr __int128 exact = __int128{1} << 53;
    if (p > -exact && p < exact && q < exact) return static_cast<double>(p) / static_cast<double>(q);
    return static_cast<double>(static_cast<long double>(p) / static_cast<long double>(q));
}

std::vector<CertKeyLine> parse_cert_key_lines(std::string_view text) {
    std::vector<CertKeyLine> out;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.substr(0, 4) != "key ") continue;
        // Fields split on spaces by hand (an istringstream per line made the
        // table cost 20 ms at start-up): key index code flat m qmin qmax leaves.
        std::array<std::string_view, 8> f{};
        std::size_t nf = 0;
        for (std::size_t at = 0; at < line.size() && nf < f.size();) {
            while (at < line.size() && line[at] == ' ') ++at;
            const std::size_t end_f = std::min(line.find(' ', at), line.size());
            if (end_f > at) f[nf++] = line.substr(at, end_f - at);
            at = end_f;
        }
        CertKeyLine k;
        int flat = -1;
        std::int64_t leaves = 0;
        auto integer = [](std::string_view t, auto& v) {
            const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
            return r.ec == std::errc() && r.ptr == t.data() + t.size();
        };
        const bool ok = nf == 8 && integer(f[1], k.index) && integer(f[3], flat) && integer(f[4], k.m) &&
                        integer(f[7], leaves);
        if (!ok || (flat != 0 && flat != 1)) throw std::runtime_error("malformed key line: " + std::string(line));
        k.code = f[2];
        k.qmin = f[5];
        k.qmax = f[6];
        k.flat = flat == 1;
        out.push_back(std::move(k));
    }
    return out;
}

std::string compare_cert_keys(const std::vector<CertKeyLine>& a, const std::vector<CertKeyLine>& b) {
    if (a.size() != b.size())
        return "key count differs: " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto &x = a[i], &y = b[i];
        if (x.index != y.index || x.code != y.code || x.flat != y.flat || x.m != y.m || x.qmin != y.qmin ||
            x.qmax != y.qmax || parse_rational(x.qmin) != parse_rational(y.qmin) ||
            parse_rational(x.qmax) != parse_rational(y.qmax))
            return "key " + std::to_string(x.index) + " (" + x.code + ") differs: qmin " + x.qmin + " vs " + y.qmin +
                   ", qmax " + x.qmax + " vs " + y.qmax;
    }
    return "";
}

const CertifiedBound* certified_bound(DiagonalRule rule, const std::array<CornerState, 4>& cs, LatticeMetric metric) {
    for (const auto& c : cs)
        if (c.sign < -1 || c.sign > 1 || static_cast<int>(c.warp) >= warp_count) return nullptr;
    const Table& t = table(rule, metric);
    const int idx = raw_index(cs);
    return t.known[static_cast<std::size_t>(idx)] ? &t.bound[static_cast<std::size_t>(idx)] : nullptr;
}

bool certified_table_available(LatticeMetric metric) {
    return table(DiagonalRule::maxmin, metric).count > 0 && table(DiagonalRule::separating, metric).count > 0;
}
std::size_t certified_key_count(DiagonalRule rule, LatticeMetric metric) { return table(rule, metric).count; }
CertifiedTheorem certified_theorem(DiagonalRule rule, LatticeMetric metric) { return table(rule, metric).theorem; }

// ---------------------------------------------------------------------------
namespace {

// Plain lattice squares and graded templates: 45°, 45°, 90°; plain rhombi:
// 60°, 60°, 60° (generic_square.hpp, unwarped_diagonal).
constexpr double lattice_deg = 45.0;
double plain_min_deg(LatticeMetric m) { return m == LatticeMetric::rhombic ? 60.0 : lattice_deg; }
double plain_max_deg(LatticeMetric m) { return m == LatticeMetric::rhombic ? 60.0 : 90.0; }

// The key of a keyed square from its stencil (mesh2d/lattice.hpp:
// KeyedStencil): its corners' states from the stencil's signs (sign keys) or,
// for a junction square (3 or 4 materials), its corners' material classes
// with its corners' warps; and the key's certified bound, null if the
// certificate lacks the key.  A junction key is in proofs/materials.cert or
// materials_fan.cert (the max-min rule cannot mesh several materials).
struct SquareKey {
    std::array<CornerState, 4> cs{};
    std::array<MaterialCorner, 4> jm{};
    bool junction = false;
    const CertifiedBound* bound = nullptr;

    std::string code() const { return junction ? junction_key_code(jm) : key_code(cs); }  // only where reported
};

SquareKey square_key(const KeyedStencil& st, DiagonalRule rule, LatticeMetric metric) {
    SquareKey key;
    key.junction = st.junction;
    for (std::size_t c = 0; c < 4; ++c) {
        key.cs[c] = {st.signs[c], st.warps[c]};
        key.jm[c] = {static_cast<std::uint16_t>(st.signs[c]), st.warps[c]};
    }
    if (key.junction) key.bound = certified_junction_bound(key.jm, rule);
    else key.bound = certified_bound(rule, key.cs, metric);
    return key;
}

// The cotangent forms of triangle `tri` in the frame of square (i, j) (cot
// is invariant under translation and scaling; rhombic: the metric's forms, in
// lattice coordinates), and whether they lie in bound b: counter-clockwise,
// every angle's ratio in [min_cot, max_cot] up to a relative 1e-9.
TriangleForms<double> square_frame_forms(const Mesh& mesh, const Lattice& lattice, std::int64_t i, std::int64_t j,
                                         const std::array<std::int32_t, 3>& tri, LatticeMetric metric) {
    std::array<Point<double>, 3> v{};
    const Vec2 o = lattice.position(i, j);
    for (int q = 0; q < 3; ++q) {
        const Vec2& x = mesh.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(q)])];
        v[static_cast<std::size_t>(q)] = {(x.x - o.x) / lattice.s, (x.y - o.y) / lattice.s};
    }
    return triangle_forms(v[0], v[1], v[2], metric);
}

bool within_bound(const TriangleForms<double>& f, const CertifiedBound& b) {
    bool ok = f.cross > 0;
    for (int q = 0; q < 3 && ok; ++q) {
        const double d = f.dot[static_cast<std::size_t>(q)];
        const double tol = 1e-9 * (std::abs(d) + f.cross * std::max({1.0, std::abs(b.max_cot), std::abs(b.min_cot)}));
        ok = d <= b.max_cot * f.cross + tol && d >= b.min_cot * f.cross - tol;
    }
    return ok;
}

// The message of a triangle outside its key's bound.
std::string violation(std::int64_t i, std::int64_t j, const std::string& key, std::int64_t k, const TriangleForms<double>& f,
                      const CertifiedBound& b, LatticeMetric metric) {
    std::ostringstream m;
    m.precision(12);
    m << "certificate violated: square (" << i << ", " << j << ") key " << key << ", triangle " << k << " has angles";
    for (int q = 0; q < 3; ++q) m << ' ' << angle_deg(f.dot[static_cast<std::size_t>(q)] / f.cross, metric);
    m << " deg (cross " << f.cross << "), certified [" << b.min_deg << ", " << b.max_deg << "] deg";
    return m.str();
}

// The keyed squares' totals of certify_squares' pass.
struct KeyedTotals {
    double gmin, gmax, kmin;  // the bounds' least min_deg and largest max_deg; kmin: keyed squares only
    std::int64_t keyed, flat, nonflat, junctions, keyed_tris;
};

// The summary's fields from the pass's totals: the bounds (a triangle of no
// keyed square is a lattice template: 45°, 45°, 90°), the counts, the first
// 20 junction squares, the not-flat squares' boxes (the first 100000) and
// the first 20 with their keys; examples are (square, key) pairs.
void fill_summary(CertifiedSummary& sum, const Lattice& lattice, const KeyedTotals& t, std::int64_t ntris,
                  std::vector<std::int64_t> junction_list, std::vector<std::pair<std::int64_t, std::string>> examples,
                  const CertifyOptions& options, LatticeMetric metric) {
    const std::int64_t nx = lattice.nx;
    double gmin = t.gmin, gmax = t.gmax;
    sum.junction_squares = t.junctions;
    std::sort(junction_list.begin(), junction_list.end());
    if (junction_list.size() > 20) junction_list.resize(20);
    sum.junction_list = std::move(junction_list);
    if (t.keyed_tris < ntris)
        gmin = std::min(gmin, plain_min_deg(metric)), gmax = std::max(gmax, plain_max_deg(metric));
    sum.min_deg = gmin;
    sum.max_deg = gmax;
    sum.keyed_min_deg = t.keyed ? t.kmin : std::numeric_limits<double>::quiet_NaN();
    sum.keyed_squares = t.keyed;
    sum.flat_squares = t.flat;
    sum.nonflat_squares = t.nonflat;
    sum.verified = options.verify;
    std::sort(examples.begin(), examples.end());
    for (std::size_t e = 0; e < examples.size() && e < 100000; ++e) {
        const Vec2 lo = lattice.position(examples[e].first % nx, examples[e].first / nx);
        sum.nonflat_boxes.push_back({lo.x, lo.y, lo.x + lattice.s, lo.y + lattice.s});
    }
    for (std::size_t e = 0; e < examples.size() && e < 20; ++e) {
        sum.nonflat_examples.push_back({examples[e].first % nx, examples[e].first / nx});
        sum.nonflat_keys.push_back(examples[e].second);
    }
}

}  // namespace

CertifiedSummary certify_keys(Mesh& mesh, const Lattice& lattice, const SquareKeys& keys, DiagonalRule rule,
                              const CertifyOptions& options) {
    CertifiedSummary sum;
    const LatticeMetric metric = keys.metric;
    if (!options.enabled || !certified_table_available(metric)) return sum;
    sum.available = true;
    const std::int64_t ntris = static_cast<std::int64_t>(mesh.triangles.size());
    const std::int64_t nx = lattice.nx;
    const std::span<const KeyedSquare> keyed_squares = keys.squares;
    if (keys.stencils.size() != keyed_squares.size()) throw std::logic_error("certify_keys: one stencil per keyed square is needed");
    Buffer<double> cell;  // every element written: lattice_deg first, then the keyed squares' bounds
    double gmin = std::numeric_limits<double>::infinity(), gmax = -gmin, kmin = gmin;
    if (options.cell_data) cell.resize(static_cast<std::size_t>(ntris));
    std::int64_t keyed = 0, flat_count = 0, nonflat = 0, junctions = 0;
    std::mutex mu;
    std::vector<std::int64_t> junction_list;
    std::vector<std::pair<std::int64_t, std::string>> examples;  // (square, key)
    std::string failure;
    std::int64_t failure_tri = -1;

    if (options.cell_data) {
#pragma omp parallel for schedule(static)
        for (std::int64_t k = 0; k < ntris; ++k) cell[static_cast<std::size_t>(k)] = plain_min_deg(metric);
    }
    std::int64_t keyed_tris = 0;
    const std::int64_t nkeyed = static_cast<std::int64_t>(keyed_squares.size());

#pragma omp parallel for schedule(dynamic, 256) reduction(min : gmin, kmin) reduction(max : gmax) \
    reduction(+ : keyed, flat_count, nonflat, keyed_tris, junctions)
    for (std::int64_t ks = 0; ks < nkeyed; ++ks) {
        const KeyedSquare& ksq = keyed_squares[static_cast<std::size_t>(ks)];
        const std::int64_t sq = ksq.square, k0 = ksq.first, k1 = ksq.first + ksq.count;
        if (k0 < 0 || ksq.count < 1 || k1 > ntris) {  // no exception may leave an OpenMP region
            std::lock_guard<std::mutex> lock(mu);
            failure = "certify_keys: bad triangle provenance for square " + std::to_string(sq);
            continue;
        }
        keyed_tris += k1 - k0;
        const std::int64_t i = sq % nx, j = sq / nx;
        const KeyedStencil& st = keys.stencils[static_cast<std::size_t>(ks)];
        const bool junction = st.junction;
        const SquareKey key = square_key(st, rule, metric);
        const CertifiedBound* b = key.bound;
        if (!b) {
            std::lock_guard<std::mutex> lock(mu);
            if (failure.empty() || k0 < failure_tri) {
                failure = std::string(junction ? "junction square (" : "square (") + std::to_string(i) + ", " +
                          std::to_string(j) + ") has key " + key.code() + ", which is not in the certificate" +
                          (junction ? " proofs/materials.cert" : "");
                failure_tri = k0;
            }
            continue;
        }
        if (junction) {
            ++junctions;
            std::lock_guard<std::mutex> lock(mu);
            junction_list.push_back(sq);
        }
        gmin = std::min(gmin, b->min_deg);
        kmin = std::min(kmin, b->min_deg);
        gmax = std::max(gmax, b->max_deg);
        for (std::int64_t k = k0; k < k1; ++k) {
            if (options.cell_data) cell[static_cast<std::size_t>(k)] = b->min_deg;
            if (!options.verify) continue;
            const TriangleForms<double> f =
                square_frame_forms(mesh, lattice, i, j, mesh.triangles[static_cast<std::size_t>(k)], metric);
            if (!within_bound(f, *b)) {
                const std::string m = violation(i, j, key.code(), k, f, *b, metric);
                std::lock_guard<std::mutex> lock(mu);
                if (failure.empty() || k < failure_tri) failure = m, failure_tri = k;
            }
        }
        ++keyed;
        // Flatness of the 12-point stencil; a stencil leaving the lattice is not flat.
        // Junction squares count as not flat: no flat theorem covers them.
        const bool inside = std::find(st.signs.begin(), st.signs.end(), off_lattice) == st.signs.end();
        if (!junction && inside && stencil_is_flat(st.signs)) ++flat_count;
        else {
            ++nonflat;
            std::lock_guard<std::mutex> lock(mu);
            examples.emplace_back(sq, key.code());
        }
    }
    if (!failure.empty()) throw std::logic_error(failure);
    fill_summary(sum, lattice, {gmin, gmax, kmin, keyed, flat_count, nonflat, junctions, keyed_tris}, ntris,
                 std::move(junction_list), std::move(examples), options, metric);
    if (options.cell_data) mesh.cell_data.emplace_back("certified_min_angle", std::move(cell));
    return sum;
}

double edge_distance_to_levelset(const LevelSet& f, Vec2 a, Vec2 b, double s) {
    const double h = 1e-6 * s;
    double worst = 0;
    for (int q = 0; q <= 8; ++q) {
        const double u = q / 8.0, x = a.x + u * (b.x - a.x), y = a.y + u * (b.y - a.y);
        const double v = f.value(x, y);
        if (v == 0) continue;
        const double gx = (f.value(x + h, y) - f.value(x - h, y)) / (2 * h);
        const double gy = (f.value(x, y + h) - f.value(x, y - h)) / (2 * h);
        const double g = std::hypot(gx, gy);
        worst = std::max(worst, g > 0 ? std::abs(v) / g : std::numeric_limits<double>::infinity());
    }
    return worst;
}

void measure_fidelity(const Mesh& mesh, const LevelSet& f, double s, CertifiedSummary& sum) {
    double worst = 0;
    std::int64_t off = 0;
    const std::int64_t n = static_cast<std::int64_t>(mesh.boundary.size());
#pragma omp parallel for schedule(static) reduction(max : worst) reduction(+ : off)
    for (std::int64_t e = 0; e < n; ++e) {
        if (mesh.boundary_tag[static_cast<std::size_t>(e)] != boundary_level_set) continue;
        const Vec2 a = mesh.vertices[static_cast<std::size_t>(mesh.boundary[static_cast<std::size_t>(e)][0])];
        const Vec2 b = mesh.vertices[static_cast<std::size_t>(mesh.boundary[static_cast<std::size_t>(e)][1])];
        if (std::abs(f.value(a.x, a.y)) > 1e-9 * s || std::abs(f.value(b.x, b.y)) > 1e-9 * s) ++off;
        worst = std::max(worst, edge_distance_to_levelset(f, a, b, s));
    }
    sum.has_fidelity = true;
    sum.max_boundary_distance = worst;
    sum.boundary_edges_off_levelset = off;
}

}  // namespace warpmesh
