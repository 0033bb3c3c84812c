// slices.cpp — meshing a range of slices of one volume (slices.hpp).
#include "warpmesh/pipeline/slices.hpp"

#include <chrono>
#include <exception>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/report/report.hpp"

namespace warpmesh {

std::optional<SliceFigures> slice_figures(const LoadedSlice& s) {
    if (!s.placed) return std::nullopt;
    return SliceFigures{s.units, s.slice.axis, s.slice.index, s.format, s.plane.origin, s.plane.x_axis, s.plane.y_axis, s.plane.normal};
}

namespace {
std::string range_text(const SliceRange& r) {
    return std::string(1, "ijk"[r.axis]) + "=" + std::to_string(r.first) + ":" + std::to_string(r.end);
}
}  // namespace

SliceBatch mesh_slices(const Volume& volume, const SliceRange& range, const SliceOptions& options,
                       const std::function<SliceMeshed(const LoadedSlice&)>& mesh_one, double read_seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::int64_t size = volume.dims[static_cast<std::size_t>(range.axis)];
    if (range.first < 0 || range.end > size || range.first >= range.end)
        throw InputError("slice range " + range_text(range) + " reaches beyond '" + volume.source + "' (" + "ijk"[range.axis] +
                         " = 0.." + std::to_string(size - 1) + ")");
    SliceBatch batch;
    batch.input = volume.source;
    batch.format = volume.format;
    batch.range = range;
    const std::int64_t n = range.end - range.first;
    batch.slices.resize(static_cast<std::size_t>(n));
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t s = 0; s < n; ++s) {
        SliceOutcome& out = batch.slices[static_cast<std::size_t>(s)];
        out.index = range.first + s;
        try {
            SliceOptions so = options;
            so.slice = SliceSpec{range.axis, out.index};
            const LoadedSlice input = load_slice(volume, so);
            out.placed = slice_figures(input);
            SliceMeshed m = mesh_one(input);
            out.report = std::move(m.report);
            out.outputs = std::move(m.outputs);
            out.warnings = std::move(m.warnings);
        } catch (const InputError& e) {
            out.skipped = e.what();
        } catch (...) {
            errors[static_cast<std::size_t>(s)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
    if (batch.meshed() == 0)
        throw InputError("slice range " + range_text(range) + ": no slice could be meshed (" + batch.slices.front().skipped +
                         "); nothing written");
    batch.read_seconds = read_seconds;
    batch.total_seconds = read_seconds + seconds_since(t0);
    return batch;
}

}  // namespace warpmesh
