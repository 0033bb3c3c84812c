// slices_report.cpp — the report of a batch of slices
// (report/slices_report.hpp) as text and JSON, and its warnings grouped.
#include "warpmesh/report/slices_report.hpp"

#include <algorithm>
#include <sstream>

#include "report_parts.hpp"

namespace warpmesh {

std::int64_t SliceBatch::meshed() const {
    std::int64_t n = 0;
    for (const SliceOutcome& s : slices) n += s.report.has_value();
    return n;
}

std::int64_t SliceBatch::triangles() const {
    std::int64_t n = 0;
    for (const SliceOutcome& s : slices)
        if (s.report) n += s.report->triangles;
    return n;
}

namespace {
// ", \"warnings\": [...]", or nothing for a slice without warnings.
std::string warnings_json(const std::vector<std::string>& warnings) {
    return warnings.empty() ? std::string() : ", \"warnings\": " + report_detail::json_strings(warnings);
}

}  // namespace

std::string to_json(const SliceBatch& b) {
    std::string json = "{\"input\": " + json_string(b.input) + ", \"format\": " + json_string(b.format) +
                       ", \"axis\": \"" + "ijk"[b.range.axis] + "\", \"first\": " + std::to_string(b.range.first) +
                       ", \"end\": " + std::to_string(b.range.end) + ", \"slices\": [";
    for (std::size_t s = 0; s < b.slices.size(); ++s) {
        const SliceOutcome& d = b.slices[s];
        json += std::string(s ? ", " : "") + "{\"index\": " + std::to_string(d.index);
        if (d.report)
            json += ", \"outputs\": " + json_string(d.outputs) + ", \"triangles\": " + std::to_string(d.report->triangles) +
                    ", \"vertices\": " + std::to_string(d.report->vertices) + ", \"area\": " + json_number(d.report->area) +
                    ", \"min_angle_deg\": " + json_number(d.report->min_angle_deg) + ", \"max_angle_deg\": " +
                    json_number(d.report->max_angle_deg) + ", \"plane\": " + (d.placed ? report_detail::slice_plane_json(*d.placed) : std::string("null")) +
                    warnings_json(d.warnings) + "}";
        else
            json += ", \"skipped\": " + json_string(d.skipped) + "}";
    }
    const std::int64_t meshed = b.meshed();
    return json + "], \"meshed\": " + std::to_string(meshed) +
           ", \"skipped\": " + std::to_string(static_cast<std::int64_t>(b.slices.size()) - meshed) +
           ", \"triangles\": " + std::to_string(b.triangles()) + ", \"read_seconds\": " + json_number(b.read_seconds) +
           ", \"total_seconds\": " + json_number(b.total_seconds) + "}\n";
}

std::string to_text(const SliceBatch& b) {
    std::ostringstream text;
    for (const SliceOutcome& d : b.slices) {
        text << "ijk"[b.range.axis] << "=" << d.index << ": ";
        if (d.report)
            text << d.report->triangles << " triangles, angles [" << d.report->min_angle_deg << ", "
                 << d.report->max_angle_deg << "] deg, area " << d.report->area << " -> " << d.outputs << "\n";
        else
            text << "skipped: " << d.skipped << "\n";
    }
    text << b.meshed() << " of " << b.slices.size() << " slices meshed, " << b.triangles() << " triangles in "
         << b.total_seconds << " s (reading " << b.read_seconds << " s)\n";
    return text.str();
}

std::vector<std::string> batch_warnings(const SliceBatch& b) {
    std::vector<std::pair<std::string, std::vector<std::int64_t>>> groups;  // warning, its slices
    for (const SliceOutcome& d : b.slices)
        for (const std::string& w : d.warnings) {
            auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& e) { return e.first == w; });
            if (g == groups.end()) g = groups.insert(groups.end(), {w, {}});
            if (g->second.empty() || g->second.back() != d.index) g->second.push_back(d.index);
        }
    std::vector<std::string> lines;
    for (const auto& [w, indices] : groups) {
        // Runs of consecutive slices as "first..last".
        std::string which = std::string(indices.size() > 1 ? "slices " : "slice ") + "ijk"[b.range.axis] + "=";
        for (std::size_t k = 0, end; k < indices.size(); k = end) {
            for (end = k + 1; end < indices.size() && indices[end] == indices[end - 1] + 1;) ++end;
            which += (k ? ", " : "") + std::to_string(indices[k]);
            if (end - k > 1) which += (end - k > 2 ? ".." : ", ") + std::to_string(indices[end - 1]);
        }
        lines.push_back(which + ": " + w);
    }
    return lines;
}

}  // namespace warpmesh
