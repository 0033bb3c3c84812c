// memory.cpp — the memory bound's admission checks (memory.hpp).
#include "warpmesh/core/memory.hpp"

#include <unistd.h>

#include <cstdio>
#include <mutex>

#include "warpmesh/core/errors.hpp"

namespace warpmesh {

std::uint64_t resident_bytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long size = 0, resident = 0;
    const int got = std::fscanf(f, "%llu %llu", &size, &resident);
    std::fclose(f);
    const long page = sysconf(_SC_PAGESIZE);
    return got == 2 && page > 0 ? resident * static_cast<std::uint64_t>(page) : 0;
}

namespace {
std::mutex call_mutex;
int calls = 0;                // MemoryCalls alive
std::uint64_t baseline = 0;   // resident_bytes() when the first of them began
}  // namespace

MemoryCall::MemoryCall() {
    const std::lock_guard lock(call_mutex);
    if (calls++ == 0) baseline = resident_bytes();
}

MemoryCall::~MemoryCall() {
    const std::lock_guard lock(call_mutex);
    if (--calls == 0) baseline = 0;
}

std::uint64_t memory_baseline() {
    const std::lock_guard lock(call_mutex);
    return baseline;
}

// The costs: peaks measured on 2048 x 2048 images of random labels (every
// lattice square warped) and on full rectangles with every output option,
// less what was resident before the stage, divided by the pixels or squares
// and rounded up (the runs are in docs/performance.md).
std::uint64_t field_bytes_per_pixel(FieldKind kind) {
    switch (kind) {
        case FieldKind::threshold: return 32;
        case FieldKind::label: return 64;
        case FieldKind::materials: return 176;
    }
    return 176;
}

std::uint64_t mesh_bytes_per_square(bool materials, bool graded) {
    if (!materials) return 112;
    return graded ? 360 : 128;  // above the material field, which is resident already
}

std::uint64_t mesh_bytes_per_material() { return 1536; }

// The peak with --optimize less the peak without, over the triangles,
// rounded up (docs/performance.md, "The per-unit costs behind --max-memory").
std::uint64_t optimize_bytes_per_triangle(bool materials) { return materials ? 128 : 64; }
std::uint64_t optimize_bytes_per_square(bool materials) { return 2 * optimize_bytes_per_triangle(materials); }

void check_memory(std::uint64_t need, std::uint64_t max_memory, const std::string& what, const std::string& how,
                  const std::string& advice) {
    const std::uint64_t resident = resident_bytes(), base = memory_baseline();
    const std::uint64_t now = resident > base ? resident - base : 0;  // what this call holds
    if (need <= max_memory && now <= max_memory - need) return;
    // The stage's own need and what the call holds already (its input, the
    // stages before), each stated, so the sum reads.
    char text[160];
    std::snprintf(text, sizeof text, " needs about %.0f MB (", static_cast<double>(need) / 1048576.0);
    std::string msg = what + text + how + ")";
    std::snprintf(text, sizeof text, " on top of the %.0f MB this call holds already, %.0f MB in all,",
                  static_cast<double>(now) / 1048576.0, static_cast<double>(now + need) / 1048576.0);
    throw OptionError("max_memory", msg + text + " more than the {max_memory} limit of " + std::to_string(max_memory >> 20) +
                                        " MB; raise {max_memory} if this machine has the memory, or " + advice);
}

}  // namespace warpmesh
