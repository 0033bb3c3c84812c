// assembly3.cpp — stage 6: the mesh from the emitted tetrahedra (boundary
// faces, tags, interfaces), the whole-lattice mesher mesh_bcc, and blocks
// (their windows, for one region and for several materials; their own
// counts and open faces) and their merge (after tiling3.cpp's check that
// they tile one lattice exactly once).
//
// Boundary faces.  A face of an output tetrahedron is on the boundary iff no
// other output tetrahedron has it.  By the stencils' construction a face can
// be unshared only if its three vertices are on the level set (warped or zero
// lattice points and cut points: the stencil's cut surface, or a background
// face with three zero vertices, e.g. of an all-zero background tetrahedron,
// which is never output)
// or if it lies on a background face with no background tetrahedron behind
// it (the lattice's cut-off; stage 5 names those faces exactly — a tetrahedron
// there also has faces shared with its neighbours, which must not become
// candidates on one side only).  The candidates — a surface-sized set — are
// matched by sorting their vertex triples; the unmatched ones are the
// boundary, oriented as their tetrahedron sees them from outside, tagged
// boundary_level_set when all three vertices are on the level set, unless
// they all lie on one face of the input's domain (a volume's hull, which
// closes a region reaching the volume's edge: mark_domain_faces), else
// boundary_domain.  With several materials (materials3.cpp) the flagged
// vertices are those on an interface, and a matched candidate whose two
// tetrahedra have different regions is an interface face.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "uniform3d.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace uniform3d {
namespace {


struct FaceRef {
    std::array<std::int32_t, 3> sorted;
    std::int64_t tet;
    int opposite;
    bool operator<(const FaceRef& o) const { return std::tie(sorted, tet, opposite) < std::tie(o.sorted, o.tet, o.opposite); }
};

// The faces of tetrahedron t (bit v: the face without vertex v) whose three
// vertices are on the level set.
unsigned level_set_faces(const TetMesh& mesh, std::int64_t t, std::span<const std::uint8_t> on) {
    const auto& tet = mesh.tets[static_cast<std::size_t>(t)];
    unsigned level = 0;
    for (std::size_t v = 0; v < 4; ++v) level |= (on[static_cast<std::size_t>(tet[v])] ? 1u : 0u) << v;
    unsigned rest = level & (level - 1);
    rest &= rest - 1;  // two set bits cleared: non-zero iff three or four were set
    if (!rest) return 0;  // most tetrahedra: no candidate face
    unsigned faces = 0;
    for (unsigned v = 0; v < 4; ++v)
        if ((level | 1u << v) == 15u) faces |= 1u << v;
    return faces;
}

// The number of faces in a face mask (no std::popcount: without -mpopcnt it
// is a library call).
int face_count(unsigned faces) { return static_cast<int>((faces & 1u) + (faces >> 1 & 1u) + (faces >> 2 & 1u) + (faces >> 3 & 1u)); }

// The faces `faces` (bit v: the face without vertex v) of tetrahedron t, at out.
FaceRef* add_faces(const TetMesh& mesh, std::int64_t t, unsigned faces, FaceRef* out) {
    const auto& tet = mesh.tets[static_cast<std::size_t>(t)];
    for (int v = 0; v < 4; ++v) {
        if (!(faces >> v & 1u)) continue;
        const auto& f = outward_face[static_cast<std::size_t>(v)];
        std::array<std::int32_t, 3> s{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
        std::sort(s.begin(), s.end());
        *out++ = {s, t, v};
    }
    return out;
}

}  // namespace

void mark_domain_faces(std::span<const Point3> vertices, std::span<std::uint8_t> on, const std::optional<Box3>& domain,
                       double spacing) {
    if (!domain) return;
    const double tol = 1e-6 * spacing;
    const std::array<double, 6> plane{domain->xmin, domain->xmax, domain->ymin, domain->ymax, domain->zmin, domain->zmax};
#pragma omp parallel for schedule(static)
    for (std::int64_t v = 0; v < static_cast<std::int64_t>(vertices.size()); ++v) {
        std::uint8_t& flag = on[static_cast<std::size_t>(v)];
        if (!flag) continue;
        const Point3 p = vertices[static_cast<std::size_t>(v)];
        const std::array<double, 3> x{p.x, p.y, p.z};
        for (std::size_t k = 0; k < 6; ++k)
            if (std::abs(x[k / 2] - plane[k]) <= tol) flag = static_cast<std::uint8_t>(flag | (2u << k));
    }
}

void find_boundary(TetMesh& mesh, std::span<const std::uint8_t> on, std::span<const CutOff> cut_off) {
    const std::int64_t T = static_cast<std::int64_t>(mesh.tets.size());
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    // The candidates: each chunk's are counted, then written in place (one
    // array of the exact size, in chunk order), then the cut-off faces.
    const auto chunk = [&](int c) { return std::pair<std::int64_t, std::int64_t>{T * c / threads, T * (c + 1) / threads}; };
    std::vector<std::int64_t> start(static_cast<std::size_t>(threads) + 1, 0);
#pragma omp parallel for schedule(static)
    for (int c = 0; c < threads; ++c) {
        std::int64_t n = 0;
        for (std::int64_t t = chunk(c).first; t < chunk(c).second; ++t) n += face_count(level_set_faces(mesh, t, on));
        start[static_cast<std::size_t>(c) + 1] = n;
    }
    for (int c = 0; c < threads; ++c) start[static_cast<std::size_t>(c) + 1] += start[static_cast<std::size_t>(c)];
    std::int64_t cut_off_faces = 0;
    for (const CutOff& c : cut_off) cut_off_faces += face_count(c.second);
    Buffer<FaceRef> faces(static_cast<std::size_t>(start.back() + cut_off_faces));  // every element written below
#pragma omp parallel for schedule(static)
    for (int c = 0; c < threads; ++c) {
        FaceRef* out = faces.data() + start[static_cast<std::size_t>(c)];
        for (std::int64_t t = chunk(c).first; t < chunk(c).second; ++t)
            if (const unsigned f = level_set_faces(mesh, t, on)) out = add_faces(mesh, t, f, out);
    }
    // A cut-off face has nothing behind it and no twin: it stays unmatched
    // (listed once even when its three vertices are on the level set).
    FaceRef* out = faces.data() + start.back();
    for (const CutOff& c : cut_off) out = add_faces(mesh, c.first, c.second, out);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end(), [](const FaceRef& a, const FaceRef& b) { return a.tet == b.tet && a.opposite == b.opposite; }), faces.end());
    mesh.boundary.clear();
    mesh.boundary_tag.clear();
    mesh.interfaces.clear();
    mesh.interface_regions.clear();
    // At most one a candidate (address space: only what is written is touched).
    mesh.boundary.reserve(faces.size()), mesh.boundary_tag.reserve(faces.size());
    mesh.interfaces.reserve(faces.size() / 2), mesh.interface_regions.reserve(faces.size() / 2);
    const auto outward = [&](const FaceRef& r) {
        const auto& tet = mesh.tets[static_cast<std::size_t>(r.tet)];
        const auto& f = outward_face[static_cast<std::size_t>(r.opposite)];
        return std::array<std::int32_t, 3>{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
    };
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i;
        while (j < faces.size() && faces[j].sorted == faces[i].sorted) ++j;
        if (j - i > 2) throw std::logic_error("mesh3d: a face in more than two tetrahedra (vertex " + std::to_string(faces[i].sorted[0]) + ")");
        const std::int32_t ra = mesh.region[static_cast<std::size_t>(faces[i].tet)];
        if (j - i == 1) {
            const std::array<std::int32_t, 3> b = outward(faces[i]);
            mesh.boundary.push_back(b);
            const std::uint8_t o0 = on[static_cast<std::size_t>(b[0])], o1 = on[static_cast<std::size_t>(b[1])],
                               o2 = on[static_cast<std::size_t>(b[2])];
            const bool level = o0 && o1 && o2 && !(o0 & o1 & o2 & domain_face_flags);
            mesh.boundary_tag.push_back(level ? boundary_level_set : boundary_domain);
        } else if (const std::int32_t rb = mesh.region[static_cast<std::size_t>(faces[i + 1].tet)]; ra != rb) {
            mesh.interfaces.push_back(outward(faces[i]));  // out of the first tetrahedron, into the other
            mesh.interface_regions.push_back({ra, rb});
        }
        i = j;
    }
}

namespace {

// The window of the cubes [lo − halo, hi + halo) ∩ the lattice.
Grid block_grid(const Lattice3& L, const CubeRange& r, std::int64_t halo) {
    bcc::Ivec lo{}, hi{};
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = static_cast<int>(2 * std::max<std::int64_t>(0, r.lo[a] - halo));
        hi[a] = static_cast<int>(2 * std::min<std::int64_t>(L.cubes[a], r.hi[a] + halo));
    }
    return Grid::window(L, lo, hi);
}

}  // namespace

Window block_window(const Lattice3& L, const CubeRange& block, const std::function<void(Window&)>& prepare) {
    for (std::int64_t halo = 2;; halo *= 2) {
        Window w;
        w.grid = block_grid(L, block, halo);
        prepare(w);
        bool whole = true;
        for (std::size_t a = 0; a < 3; ++a) whole = whole && block.lo[a] - halo <= 0 && block.hi[a] + halo >= L.cubes[a];
        bool exact = true;  // no tainted point among the block's: doubled coordinates [2 lo − 1, 2 hi]
        for (std::int64_t p = 0; p < w.grid.count() && exact && !whole; ++p) {
            if (!w.taint[static_cast<std::size_t>(p)]) continue;
            const bcc::Ivec q = w.grid.point(p);
            bool inside = true;
            for (std::size_t a = 0; a < 3; ++a) inside = inside && q[a] >= 2 * block.lo[a] - 1 && q[a] <= 2 * block.hi[a];
            exact = !inside;
        }
        if (exact || whole) return w;
    }
}

void check_options(const BccOptions& o) {
    const bcc::Alphas a = o.alphas;
    const bool ok = a.long_den > 0 && a.short_den > 0 && a.long_num > 0 && a.short_num > 0 && 2 * a.long_num < a.long_den &&
                    2 * a.short_num < a.short_den;
    if (!ok) throw InputError("the alphas must lie in (0, 1/2)");
    if (o.face_rule != FaceRule::parity && o.face_rule != FaceRule::delaunay) throw InputError("the face rule must be parity or delaunay");
}

void check_block(const Lattice3& lattice, const CubeRange& block, const std::string& what) {
    for (std::size_t a = 0; a < 3; ++a)
        if (!(block.lo[a] >= 0 && block.lo[a] <= block.hi[a] && block.hi[a] <= lattice.cubes[a]))
            throw InputError(what + ": the block is not a range of the lattice's cubes");
}

TetBlock make_block(const Window& w, const CubeRange& range, const BccOptions& o, std::vector<std::uint64_t>&& vertex_key,
                    std::span<const Point3> vertices, std::vector<std::uint8_t>&& on, std::span<const std::array<std::int32_t, 4>> tets,
                    std::vector<std::uint64_t>&& tet_key, std::span<const CutOff> cut_off) {
    TetBlock b;
    b.lattice = w.grid.lattice, b.range = range, b.face_rule = o.face_rule, b.alphas = o.alphas;
    for (const auto& [p, position] : w.warped) {
        const bcc::Ivec q = w.grid.point(p);
        bool own = true;
        for (std::size_t a = 0; a < 3; ++a) {
            const std::int64_t c = std::min<std::int64_t>(q[a] / 2, b.lattice.cubes[a] - 1);
            own = own && c >= range.lo[a] && c < range.hi[a];
        }
        b.warped += own;
    }
    b.vertex_key = std::move(vertex_key);
    b.vertices.assign(vertices.begin(), vertices.end());
    b.on_level_set = std::move(on);
    b.tets.assign(tets.begin(), tets.end());
    b.tet_key = std::move(tet_key);
    b.lattice_edge.assign(b.tets.size(), 0);
    for (const CutOff& c : cut_off) b.lattice_edge[static_cast<std::size_t>(c.first)] = c.second;
    return b;
}

namespace {

// f sampled, cut and warped on the window's grid (set beforehand).
void prepare(const LevelSet3& f, const BccOptions& o, bool blocked, Window& w) {
    // Per point: f (8), sign, warp, cut mask (3), first cut (4), the
    // numbering's use byte and two ids (9); the cut parameters are surface-sized.
    check_memory(static_cast<std::uint64_t>(w.grid.count()) * 24, o.max_memory,
                 "the 3D lattice of " + std::to_string(w.grid.count()) + " points", "24 bytes a lattice point",
                 "choose a larger {spacing}");
    sample_signs(f, w);
    find_cuts(f, w);
    Buffer<double>().swap(w.value);  // f is not needed past the cut points
    warp_points(o.alphas, w, blocked);
}


TetMesh to_mesh(Emitted&& e) {
    TetMesh m;
    m.vertices = std::move(e.vertices);
    m.tets = std::move(e.tets);
    m.region.resize(m.tets.size());
    std::fill(m.region.begin(), m.region.end(), 1);
    find_boundary(m, e.on_level_set, e.cut_off);
    return m;
}

}  // namespace

void prepare_window(const LevelSet3& f, const BccOptions& o, Window& w) { prepare(f, o, false, w); }

BccMesh finish_mesh(Emitted&& e, const LevelSet3& f, const Lattice3& lattice, const BccOptions& o, std::int64_t warped) {
    if (e.uncovered_keys > 0)
        throw std::logic_error("mesh3d verify: " + std::to_string(e.uncovered_keys) + " background tetrahedra have a key that " +
                               o.verify->source + " does not list (first: " + e.first_uncovered + ")");
    if (e.key_claim_failures > 0)
        throw std::logic_error("mesh3d verify: " + std::to_string(e.key_claim_failures) + " tetrahedra fail their key's claim in " +
                               o.verify->source + " (first key: " + e.first_key_claim_failure + ")");
    if (e.tets.empty())
        throw InputError("the region is empty: no tetrahedron inside at spacing " + std::to_string(lattice.spacing) + " (" + f.describe() + ")");
    BccMesh r;
    r.lattice_points = lattice.point_count();
    r.background_tets = 12 * lattice.cubes[0] * lattice.cubes[1] * lattice.cubes[2];
    r.cut_points = e.cut_points;
    r.warped = warped;
    r.all_zero_left_out = e.all_zero_left_out;
    r.verified = o.verify != nullptr;
    mark_domain_faces(std::span<const Point3>(e.vertices.data(), e.vertices.size()), e.on_level_set, f.domain(), lattice.spacing);
    r.mesh = to_mesh(std::move(e));
    return r;
}

}  // namespace uniform3d

BccMesh mesh_bcc(const LevelSet3& f, const Lattice3& lattice, const BccOptions& o) {
    using namespace uniform3d;
    check_options(o);
    const ThreadCount threads(o.threads);
    const auto start = std::chrono::steady_clock::now();
    const CubeRange all{{0, 0, 0}, lattice.cubes};
    Window w;
    w.grid = Grid::whole(lattice);
    prepare(f, o, false, w);
    Emitted e = emit_tets(w, all, false, o.max_memory, o.face_rule, o.verify);
    const std::int64_t warped = w.warp_count;
    w = Window{};
    BccMesh r = finish_mesh(std::move(e), f, lattice, o, warped);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

TetBlock mesh_bcc_block(const LevelSet3& f, const Lattice3& lattice, const BccOptions& o, const CubeRange& block) {
    using namespace uniform3d;
    check_options(o);
    check_block(lattice, block, "mesh_bcc_block");
    const ThreadCount threads(o.threads);
    const Window w = block_window(lattice, block, [&](Window& win) { prepare(f, o, true, win); });
    Emitted e = emit_tets(w, block, true, o.max_memory, o.face_rule);
    mark_domain_faces(std::span<const Point3>(e.vertices.data(), e.vertices.size()), e.on_level_set, f.domain(), lattice.spacing);
    TetBlock b = make_block(w, block, o, std::move(e.vertex_key), e.vertices, std::vector<std::uint8_t>(e.on_level_set), e.tets,
                            std::move(e.tet_key), e.cut_off);
    b.all_zero_left_out = e.all_zero_left_out;
    // The block's own boundary: its level-set faces are the open ones.
    TetMesh own = to_mesh(std::move(e));
    for (std::size_t i = 0; i < own.boundary.size(); ++i)
        if (own.boundary_tag[i] == boundary_level_set) b.open_faces.push_back(own.boundary[i]);
    return b;
}

namespace {

struct KeyedVertex {
    std::uint64_t key;
    Point3 p;
    std::uint8_t on;
};

// The blocks' vertices by key, each once; throws if two blocks place one differently.
std::vector<KeyedVertex> merged_vertices(std::span<const TetBlock> blocks) {
    std::vector<KeyedVertex> vs;
    for (const TetBlock& b : blocks)
        for (std::size_t i = 0; i < b.vertex_key.size(); ++i) vs.push_back({b.vertex_key[i], b.vertices[i], b.on_level_set[i]});
    std::sort(vs.begin(), vs.end(), [](const KeyedVertex& a, const KeyedVertex& b) { return a.key < b.key; });
    std::vector<KeyedVertex> unique;
    for (const KeyedVertex& v : vs) {
        if (!unique.empty() && unique.back().key == v.key) {
            if (unique.back().p.x != v.p.x || unique.back().p.y != v.p.y || unique.back().p.z != v.p.z)
                throw std::invalid_argument("merge_tet_blocks: two blocks place vertex " + std::to_string(v.key) + " differently");
            continue;
        }
        unique.push_back(v);
    }
    return unique;
}

// The blocks' region names, the same in every block (empty: one region).
std::vector<std::pair<std::int32_t, std::string>> merged_region_names(std::span<const TetBlock> blocks) {
    for (const TetBlock& b : blocks) {
        if (b.region_names != blocks.front().region_names)
            throw std::invalid_argument("merge_tet_blocks: the blocks name different regions (blocks of different meshes)");
        if (!b.region.empty() && b.region.size() != b.tets.size())
            throw std::invalid_argument("merge_tet_blocks: a block's regions do not match its tetrahedra");
    }
    return blocks.empty() ? std::vector<std::pair<std::int32_t, std::string>>{} : blocks.front().region_names;
}

// Throws unless a block's arrays agree in length and index its vertices,
// and every tetrahedron lies in one of its cubes (its key names its
// background tetrahedron's cube: 48 c + 4 i + k for one region, 24 (12 c +
// i) + k for several materials).
void check_block_arrays(std::span<const TetBlock> blocks) {
    for (std::size_t n = 0; n < blocks.size(); ++n) {
        const TetBlock& b = blocks[n];
        const std::size_t V = b.vertices.size(), T = b.tets.size();
        bool ok = b.vertex_key.size() == V && b.on_level_set.size() == V && b.tet_key.size() == T && b.lattice_edge.size() == T &&
                  (b.region.empty() || b.region.size() == T);
        for (const auto& t : b.tets)
            for (const std::int32_t v : t) ok = ok && v >= 0 && static_cast<std::size_t>(v) < V;
        for (const auto& f : b.open_faces)
            for (const std::int32_t v : f) ok = ok && v >= 0 && static_cast<std::size_t>(v) < V;
        if (!ok) throw std::invalid_argument("merge_tet_blocks: block " + std::to_string(n) + "'s arrays do not fit together");
        const std::array<std::int64_t, 3>& C = b.lattice.cubes;
        const std::uint64_t per_cube = b.region.empty() ? 48 : 288;
        for (const std::uint64_t key : b.tet_key) {
            const std::int64_t c = static_cast<std::int64_t>(key / per_cube);
            const std::array<std::int64_t, 3> x{c % C[0], c / C[0] % C[1], c / (C[0] * C[1])};
            for (std::size_t a = 0; a < 3; ++a)
                if (x[a] < b.range.lo[a] || x[a] >= b.range.hi[a])
                    throw std::invalid_argument("merge_tet_blocks: block " + std::to_string(n) +
                                                " has a tetrahedron outside its cube range (a block altered after it was made)");
        }
    }
}

}  // namespace

BccMesh merge_bcc_blocks(std::span<const TetBlock> blocks) {
    if (const auto problem = tiling_problem(blocks)) throw std::invalid_argument(*problem);
    check_block_arrays(blocks);
    const std::vector<KeyedVertex> unique = merged_vertices(blocks);
    struct T {
        std::uint64_t key;
        std::array<std::int32_t, 4> tet;
        std::int32_t region;
        std::uint8_t cut_off;
    };
    BccMesh r;
    TetMesh& m = r.mesh;
    m.region_names = merged_region_names(blocks);
    std::vector<T> ts;
    for (const TetBlock& b : blocks)
        for (std::size_t i = 0; i < b.tets.size(); ++i) {
            std::array<std::int32_t, 4> t{};
            for (std::size_t k = 0; k < 4; ++k) {
                const std::uint64_t key = b.vertex_key[static_cast<std::size_t>(b.tets[i][k])];
                t[k] = static_cast<std::int32_t>(
                    std::lower_bound(unique.begin(), unique.end(), key, [](const KeyedVertex& a, std::uint64_t k2) { return a.key < k2; }) -
                    unique.begin());
            }
            ts.push_back({b.tet_key[i], t, b.region.empty() ? 1 : b.region[i], b.lattice_edge[i]});
        }
    std::sort(ts.begin(), ts.end(), [](const T& a, const T& b) { return a.key < b.key; });
    for (std::size_t i = 1; i < ts.size(); ++i)
        if (ts[i].key == ts[i - 1].key) throw std::invalid_argument("merge_tet_blocks: two blocks give the same tetrahedron");
    m.vertices.resize(unique.size());
    std::vector<std::uint8_t> on(unique.size());
    for (std::size_t i = 0; i < unique.size(); ++i) m.vertices[i] = unique[i].p, on[i] = unique[i].on;
    m.tets.resize(ts.size());
    m.region.resize(ts.size());
    std::vector<uniform3d::CutOff> cut_off;
    for (std::size_t i = 0; i < ts.size(); ++i) {
        m.tets[i] = ts[i].tet;
        m.region[i] = ts[i].region;
        if (ts[i].cut_off) cut_off.push_back({static_cast<std::int64_t>(i), ts[i].cut_off});
    }
    uniform3d::find_boundary(m, on, cut_off);
    const Lattice3& L = blocks.front().lattice;
    const std::uint64_t P = static_cast<std::uint64_t>(L.point_count());
    r.lattice_points = L.point_count();
    r.background_tets = 12 * L.cubes[0] * L.cubes[1] * L.cubes[2];
    for (const KeyedVertex& v : unique) r.cut_points += v.key >= P && v.key < 8 * P;
    for (const TetBlock& b : blocks) {
        r.warped += b.warped, r.all_zero_left_out += b.all_zero_left_out;
        r.all_zero_filled += b.all_zero_filled, r.all_zero_voids += b.all_zero_voids;
        r.junction_background_tets += b.junction_background_tets, r.junction_tets += b.junction_tets;
    }
    return r;
}

TetMesh merge_tet_blocks(std::span<const TetBlock> blocks) { return merge_bcc_blocks(blocks).mesh; }

}  // namespace warpmesh
