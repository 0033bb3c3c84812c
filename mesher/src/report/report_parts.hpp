// report_parts.hpp — the pieces the report module's files share (private to
// src/report/): the 2D report's JSON object, written field by field, and the
// sections of it that live in their own files.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/report/report.hpp"

namespace warpmesh::report_detail {

// One JSON object in the 2D report's layout: "{\n  \"key\": value,\n  ...\n}\n".
class JsonObject {
public:
    void field(std::string_view key, const std::string& value) {
        if (text_.size() > 2) text_ += ",\n";
        text_ += "  " + json_string(key) + ": " + value;
    }
    std::string close() const { return text_ + "\n}\n"; }

private:
    std::string text_ = "{\n";
};

// A JSON array of strings, e.g. warnings: ["a", "b"].
std::string json_strings(const std::vector<std::string>& items);

// A number for the text report: shortest of `digits` significant digits
// ("%g"-like), "n/a" when not finite.
std::string fmt(double x, int digits = 6);

// The quality's fields (quality_json's), in order.
void quality_fields(JsonObject& json, const QualityReport& q);

// The "plane" object of a slice's placement (a mesh's and the slice batch's).
std::string slice_plane_json(const SliceFigures& slice);

// The multi-material part (material_report.cpp): its fields and its lines.
void material_fields(JsonObject& json, const MaterialsFigures& m);
std::string materials_text(const MaterialsFigures& m);

// The warning for a material that got no cell ("triangle", "tetrahedron")
// at this spacing, in 2D's and 3D's reports alike.
std::string lost_material_warning(std::int32_t tag, const std::string& name, std::string_view cell);

}  // namespace warpmesh::report_detail
