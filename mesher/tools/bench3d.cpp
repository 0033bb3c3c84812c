// bench3d.cpp — the 3D mesher's speed and memory on one input (scripts/bench.sh
// --3d).  A library client only: mesh3d on a shape or a volume, no file
// written; prints one line of key=value figures: tetrahedra, meshing seconds
// (mesh3d's own clock: lattice to boundary faces, without the quality pass),
// tetrahedra per second, the CPU seconds of the mesh3d call (user + system,
// all threads: on a shared machine the figure that does not depend on the
// load) and tetrahedra per CPU second, peak resident bytes per tetrahedron (VmHWM of the
// whole process, the volume and its level set included), the peak of the
// mesh3d call beyond what the process held before it (the volume, and for
// one region its level set) per tetrahedron, the report's dihedral extremes
// and certification counts.
//
// With --materials (every label, or a list, of a label volume: several
// materials), the mesh3d call is the whole multi-material pipeline: the
// material field built from the volume, the lattice, the meshing stage,
// boundary and interfaces, certification counts and the per-material
// figures (not the quality pass unless --quality).
//
//   warpmesh-bench3d --shape SPEC | --volume FILE [--label L,...|nonzero | --materials all|L,...] [--iso V]
//                    --spacing S [--face-rule parity|delaunay] [--threads N] [--max-memory MB]
//                    [--graded [--max-size H] [--grading G]] [--quality] [--verify] [--check]
#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/io/volume.hpp"

namespace {

// A field of /proc/self/status in bytes (VmHWM: the peak resident set,
// VmRSS: the current one).
std::uint64_t status_bytes(const std::string& field) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(field + ":", 0) == 0) return std::stoull(line.substr(field.size() + 1)) * 1024;
    return 0;
}
std::uint64_t peak_rss() { return status_bytes("VmHWM"); }

// Resets VmHWM to the current resident set (Linux: clear_refs 5), so that
// the peak measured afterwards is the peak from here on; false if refused.
bool reset_peak_rss() {
    std::ofstream out("/proc/self/clear_refs");
    out << "5";
    out.flush();
    return static_cast<bool>(out);
}

// CPU seconds (user + system) of the whole process so far.
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace warpmesh;
    std::string shape, volume_path, label, materials;
    std::optional<double> iso;
    Mesh3dOptions o;
    o.quality = false;
    bool check = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw InputError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--shape") shape = next();
        else if (a == "--volume") volume_path = next();
        else if (a == "--label") label = next();
        else if (a == "--materials") materials = next();
        else if (a == "--iso") iso = std::stod(next());
        else if (a == "--spacing") o.spacing = std::stod(next());
        else if (a == "--face-rule") {
            const std::optional<FaceRule> rule = parse_face_rule(next());
            if (!rule) {
                std::cerr << "--face-rule expects parity or delaunay\n";
                return 2;
            }
            o.face_rule = *rule;
        } else if (a == "--threads") o.threads = std::stoi(next());
        else if (a == "--max-memory") o.max_memory = std::stoull(next()) << 20;
        else if (a == "--graded") o.graded = true;
        else if (a == "--max-size") o.max_size = std::stod(next());
        else if (a == "--grading") o.grading = std::stod(next());
        else if (a == "--quality") o.quality = true;
        else if (a == "--verify") o.verify = true;
        else if (a == "--check") check = true;
        else {
            std::cerr << "usage: warpmesh-bench3d --shape SPEC | --volume FILE [--label L,...|nonzero | --materials all|L,...] [--iso V] --spacing S [--face-rule parity|delaunay] [--threads N] [--max-memory MB] [--graded [--max-size H] [--grading G]] [--quality] [--verify] [--check]\n";
            return 2;
        }
    }
    try {
        std::unique_ptr<LevelSet3> f;
        std::optional<Volume> v;
        if (!shape.empty()) {
            f = parse_shape3(shape);
        } else {
            v = read_volume(volume_path);
            if (!materials.empty()) {
                o.materials = materials;
            } else {
                VolumeLevelSet3Options vo;
                if (!label.empty()) vo.mode = label_options(label);
                vo.mode.iso = iso;
                f = make_volume_levelset3(*v, vo);
            }
        }
        const Mesh3dInput input = f ? Mesh3dInput(std::cref(*f)) : Mesh3dInput(std::cref(*v));
        const bool reset = reset_peak_rss();
        const double before = static_cast<double>(status_bytes("VmRSS"));
        const double cpu0 = cpu_seconds();
        const Mesh3dResult result = mesh3d(input, o);
        const TetMesh& m = result.mesh;
        const Mesh3dReport& r = result.report;
        const double cpu = cpu_seconds() - cpu0;
        const double peak = static_cast<double>(peak_rss()), tets = static_cast<double>(r.tets);
        std::printf("tets=%lld vertices=%lld seconds=%.3f tets_per_second=%.0f cpu_seconds=%.3f tets_per_cpu_second=%.0f peak_bytes_per_tet=%.1f",
                    static_cast<long long>(r.tets), static_cast<long long>(r.vertices), r.seconds, tets / r.seconds, cpu, tets / cpu,
                    peak / tets);
        if (reset) std::printf(" call_peak_bytes_per_tet=%.1f", (peak - before) / tets);
        if (r.materials) {
            int kept = 0;
            for (const auto& x : r.materials->materials) kept += x.tets > 0;
            std::printf(" materials=%zu kept=%d", r.materials->materials.size(), kept);
        }
        if (o.quality)
            std::printf(" min_dihedral=%.3f max_dihedral=%.3f radius_ratio_min=%.4f boundary_vertex_f_max=%.3g boundary_centroid_f_max=%.3g",
                        r.quality.min_dihedral_deg, r.quality.max_dihedral_deg, r.quality.radius_ratio_min, r.quality.boundary_vertex_f_max, r.quality.boundary_centroid_f_max);
        if (check) std::printf(" check_ok=%d", check_tet_mesh(m).ok ? 1 : 0);
        if (r.graded) std::printf(" template_tets=%lld longest_edge=%.6g", static_cast<long long>(r.graded->template_tets), r.graded->longest_edge);
        std::printf(" certified=%lld uncertified=%lld verified=%d boundary_faces=%lld\n", static_cast<long long>(r.certified_tets),
                    static_cast<long long>(r.uncertified_tets), r.verified ? 1 : 0, static_cast<long long>(r.boundary_faces));
        for (const auto& w : r.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        return m.tets.empty() ? 1 : 0;
    } catch (const InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
