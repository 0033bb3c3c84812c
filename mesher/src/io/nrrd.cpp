// nrrd.cpp — NRRD volumes (teem's "nearly raw raster data",
// http://teem.sourceforge.net/nrrd/format.html), versions NRRD0001-0005.
//
// Read: attached headers (.nrrd, data after the first blank line) and
// detached ones (.nhdr, `data file:` one file, relative to the header's
// directory); 2-D and 3-D scalar data of types int8/uint8, int16/uint16,
// int32/uint32, float and double (every spelling the format allows);
// encodings raw, gzip and ascii; `endian`; `line skip` and `byte skip`
// (-1: the data ends the file; for gzip the skip is applied after
// inflating); geometry from `space directions` and `space origin`, or
// `spacings`.  Refused with a message: other types (64-bit integers, block),
// encodings (bzip2, hex), more than 3 axes, `data file: LIST` or a pattern,
// oblique or sheared `space directions`, a `none` direction on a spatial
// axis, sizes that do not fit the data or the limits.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "volume_detail.hpp"

namespace warpmesh {
namespace {

using namespace volume_detail;

[[noreturn]] void bad(const std::string& name, const std::string& what) { fail("NRRD", name, what); }

std::string trim(std::string s) {
    const auto a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return {};
    const auto b = s.find_last_not_of(" \t\r");
    return s.substr(a, b - a + 1);
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

double number(const std::string& name, const std::string& field, const std::string& text) {
    const std::string t = trim(text);
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE)
        bad(name, "malformed header: '" + field + "' has '" + t + "', not a number");
    return v;
}

std::vector<std::string> words(const std::string& s) {
    std::istringstream in(s);
    std::vector<std::string> w;
    for (std::string x; in >> x;) w.push_back(x);
    return w;
}

// "(1,0,0)" → {1, 0, 0}; "none" → empty.
std::vector<double> vector_of(const std::string& name, const std::string& field, const std::string& text) {
    const std::string t = trim(text);
    if (t == "none") return {};
    if (t.size() < 2 || t.front() != '(' || t.back() != ')')
        bad(name, "malformed header: '" + field + "' has '" + t + "', expected a vector such as (1,0,0)");
    std::vector<double> v;
    std::string item;
    std::istringstream in(t.substr(1, t.size() - 2));
    while (std::getline(in, item, ',')) v.push_back(number(name, field, item));
    return v;
}

// The vectors of `space directions`: "(1,0,0) (0,1,0) none".
std::vector<std::vector<double>> vectors_of(const std::string& name, const std::string& field, const std::string& text) {
    std::vector<std::vector<double>> out;
    std::size_t p = 0;
    while ((p = text.find_first_not_of(" \t\r", p)) != std::string::npos) {
        const std::size_t q = text[p] == '(' ? text.find(')', p) : text.find_first_of(" \t", p);
        const std::size_t e = q == std::string::npos ? text.size() : (text[p] == '(' ? q + 1 : q);
        out.push_back(vector_of(name, field, text.substr(p, e - p)));
        p = e;
    }
    return out;
}

bool sample_type(std::string t, Sample* s) {
    static const std::map<std::string, Sample> types = {
        {"signed char", Sample::i8},        {"int8", Sample::i8},           {"int8_t", Sample::i8},
        {"uchar", Sample::u8},              {"unsigned char", Sample::u8},  {"uint8", Sample::u8},
        {"uint8_t", Sample::u8},            {"short", Sample::i16},         {"short int", Sample::i16},
        {"signed short", Sample::i16},      {"signed short int", Sample::i16}, {"int16", Sample::i16},
        {"int16_t", Sample::i16},           {"ushort", Sample::u16},        {"unsigned short", Sample::u16},
        {"unsigned short int", Sample::u16}, {"uint16", Sample::u16},       {"uint16_t", Sample::u16},
        {"int", Sample::i32},               {"signed int", Sample::i32},    {"int32", Sample::i32},
        {"int32_t", Sample::i32},           {"uint", Sample::u32},          {"unsigned int", Sample::u32},
        {"uint32", Sample::u32},            {"uint32_t", Sample::u32},      {"float", Sample::f32},
        {"double", Sample::f64}};
    const auto it = types.find(lower(trim(t)));
    if (it == types.end()) return false;
    *s = it->second;
    return true;
}

std::vector<std::uint8_t> read_file_bytes(const std::string& name, const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) bad(name, "data file '" + path + "' is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) bad(name, "cannot open data file '" + path + "': " + std::strerror(errno));
    std::vector<std::uint8_t> bytes;
    std::vector<char> buf(1 << 16);
    while (in) {
        in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
        bytes.insert(bytes.end(), buf.data(), buf.data() + in.gcount());
    }
    if (in.bad()) bad(name, "read error in data file '" + path + "'");
    return bytes;
}

}  // namespace

Volume decode_nrrd(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits,
                   const std::string& dir) {
    // --- header: lines up to the first empty one (or the end of the file)
    std::map<std::string, std::string> field;
    std::size_t pos = 0;
    bool attached = false;
    bool first = true;
    while (pos < bytes.size()) {
        std::size_t e = pos;
        while (e < bytes.size() && bytes[e] != '\n') ++e;
        std::string line(reinterpret_cast<const char*>(bytes.data() + pos), e - pos);
        pos = e < bytes.size() ? e + 1 : e;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (first) {
            if (line.size() != 8 || line.compare(0, 7, "NRRD000") != 0 || line[7] < '1' || line[7] > '5')
                bad(name, "malformed header: magic '" + line.substr(0, 16) + "' is not NRRD0001..NRRD0005");
            first = false;
            continue;
        }
        if (line.empty()) {
            attached = true;
            break;
        }
        if (line[0] == '#') continue;
        if (line.find(":=") != std::string::npos && line.find(":=") < line.find(": ")) continue;  // key/value pair
        const std::size_t c = line.find(": ");
        if (c == std::string::npos) bad(name, "malformed header: line '" + line.substr(0, 60) + "' is not 'field: value'");
        field[lower(trim(line.substr(0, c)))] = trim(line.substr(c + 2));
    }
    auto get = [&](std::initializer_list<const char*> keys) -> std::optional<std::string> {
        for (const char* k : keys)
            if (const auto it = field.find(k); it != field.end()) return it->second;
        return std::nullopt;
    };
    auto need = [&](const char* key) {
        const auto v = get({key});
        if (!v) bad(name, std::string("malformed header: no '") + key + "' field");
        return *v;
    };

    // --- dimension, sizes, type, encoding, endian
    const double dim_d = number(name, "dimension", need("dimension"));
    if (dim_d != 2 && dim_d != 3)
        bad(name, "dimension " + trim(need("dimension")) + ": only 2-D and 3-D scalar volumes are read");
    const int dim = static_cast<int>(dim_d);
    const auto size_words = words(need("sizes"));
    if (static_cast<int>(size_words.size()) != dim)
        bad(name, "malformed header: 'sizes' has " + std::to_string(size_words.size()) + " entries for dimension " +
                      std::to_string(dim));
    std::vector<std::uint64_t> sizes;
    for (const auto& w : size_words) {
        std::uint64_t v = 0;
        for (char ch : w) {
            if (ch < '0' || ch > '9' || v > (std::uint64_t{1} << 60)) bad(name, "malformed header: size '" + w + "'");
            v = v * 10 + static_cast<std::uint64_t>(ch - '0');
        }
        sizes.push_back(v);
    }
    Sample type{};
    const std::string type_text = need("type");
    if (!sample_type(type_text, &type))
        bad(name, "unsupported type '" + type_text +
                      "' (read: 8-, 16- and 32-bit signed and unsigned integers, float, double)");
    const std::size_t b = sample_bytes(type);
    const std::uint64_t n = checked_voxels("NRRD", name, sizes, b, limits);
    const std::string encoding = lower(need("encoding"));
    const bool gz = encoding == "gzip" || encoding == "gz";
    const bool ascii = encoding == "ascii" || encoding == "text" || encoding == "txt";
    if (encoding != "raw" && !gz && !ascii)
        bad(name, "unsupported encoding '" + encoding + "' (read: raw, gzip, ascii)");
    bool swap = false;
    if (b > 1 && !ascii) {
        const auto endian = get({"endian"});
        if (!endian) bad(name, "malformed header: no 'endian' field for a " + std::to_string(b) + "-byte type");
        const std::string e = lower(*endian);
        if (e != "little" && e != "big") bad(name, "malformed header: endian '" + *endian + "' is not little or big");
        swap = (e == "little") != host_is_little_endian();
    }

    // --- the data bytes
    std::vector<std::uint8_t> own;
    std::span<const std::uint8_t> data;
    if (const auto file = get({"data file", "datafile"})) {
        const auto w = words(*file);
        if (w.size() != 1 || w[0] == "LIST" || file->find('%') != std::string::npos)
            bad(name, "'data file: " + *file + "': only a single detached data file is read");
        if (dir.empty()) bad(name, "detached data file '" + *file + "' cannot be read from memory");
        std::filesystem::path p(*file);
        if (p.is_relative()) p = std::filesystem::path(dir) / p;
        own = read_file_bytes(name, p.string());
        data = own;
    } else {
        if (!attached) bad(name, "truncated: the header has no blank line and no 'data file', so there is no data");
        data = bytes.subspan(pos);
    }
    if (const auto ls = get({"line skip", "lineskip"})) {
        const double k = number(name, "line skip", *ls);
        if (!(k >= 0) || k != std::floor(k)) bad(name, "malformed header: line skip '" + *ls + "'");
        for (double q = 0; q < k; ++q) {
            std::size_t e = 0;
            while (e < data.size() && data[e] != '\n') ++e;
            if (e == data.size()) bad(name, "truncated data: fewer lines than 'line skip' " + *ls);
            data = data.subspan(e + 1);
        }
    }
    double byte_skip = 0;
    if (const auto bs = get({"byte skip", "byteskip"})) {
        byte_skip = number(name, "byte skip", *bs);
        if (!(byte_skip >= -1 && byte_skip <= 1e15) || byte_skip != std::floor(byte_skip) ||
            (byte_skip == -1 && !(encoding == "raw")))
            bad(name, "malformed header: byte skip '" + *bs + "' (-1 only with raw encoding)");
    }
    const std::uint64_t need_bytes = n * b;
    Volume v;
    v.format = "NRRD";
    v.source = name;
    if (ascii) {
        if (byte_skip > 0) data = data.subspan(std::min<std::size_t>(data.size(), static_cast<std::size_t>(byte_skip)));
        std::string text(reinterpret_cast<const char*>(data.data()), data.size());
        std::vector<double> values;
        values.reserve(std::min<std::size_t>(n, text.size() / 2 + 1));
        const char* p = text.c_str();
        while (values.size() < n) {
            while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
            if (!*p) break;
            char* end = nullptr;
            const double x = std::strtod(p, &end);
            if (end == p || !std::isfinite(x)) bad(name, "malformed ascii data at value " + std::to_string(values.size()));
            values.push_back(x);
            p = end;
        }
        if (values.size() < n)
            bad(name, "truncated data: expected " + std::to_string(n) + " values, found " + std::to_string(values.size()));
        v.integer_valued = true;
        for (double x : values) v.integer_valued = v.integer_valued && x == std::floor(x);
        v.values = std::move(values);
    } else {
        std::vector<std::uint8_t> inflated;
        if (gz) {
            // deflate cannot compress more than about 1032:1: refuse data that
            // is too short to hold the voxels before inflating anything.
            if (static_cast<double>(data.size()) * 1032.0 + 1024 < static_cast<double>(need_bytes))
                bad(name, "truncated data: " + std::to_string(data.size()) + " gzip bytes cannot hold " +
                              std::to_string(need_bytes) + " bytes of voxels");
            const std::uint64_t skip = static_cast<std::uint64_t>(byte_skip);
            inflated = gunzip(data, static_cast<std::size_t>(need_bytes + skip), name);
            if (inflated.size() < need_bytes + skip)
                bad(name, "truncated data: gzip data inflates to " + std::to_string(inflated.size()) + " bytes, expected " +
                              std::to_string(need_bytes + skip));
            data = std::span<const std::uint8_t>(inflated).subspan(static_cast<std::size_t>(skip));
        } else {
            if (byte_skip == -1) {
                if (data.size() < need_bytes)
                    bad(name, "truncated data: expected " + std::to_string(need_bytes) + " bytes, found " +
                                  std::to_string(data.size()));
                data = data.subspan(data.size() - need_bytes);
            } else {
                if (byte_skip > static_cast<double>(data.size()))
                    bad(name, "truncated data: byte skip beyond the end of the data");
                data = data.subspan(static_cast<std::size_t>(byte_skip));
            }
            if (data.size() < need_bytes)
                bad(name, "truncated data: expected " + std::to_string(need_bytes) + " bytes of voxels, found " +
                              std::to_string(data.size()));
        }
        v.values = decode_samples("NRRD", name, data, type, swap, n, &v.integer_valued);
    }
    for (int a = 0; a < 3; ++a) v.dims[a] = a < dim ? static_cast<std::int64_t>(sizes[a]) : 1;

    // --- geometry
    if (const auto sp = get({"space"})) v.space = *sp;
    if (const auto dirs = get({"space directions"})) {
        const auto vs = vectors_of(name, "space directions", *dirs);
        if (static_cast<int>(vs.size()) != dim)
            bad(name, "malformed header: 'space directions' has " + std::to_string(vs.size()) + " entries for dimension " +
                          std::to_string(dim));
        for (int a = 0; a < dim; ++a) {
            if (vs[a].empty()) bad(name, "'space directions' is 'none' for axis " + std::to_string(a) + ": not a spatial volume");
            if (vs[a].size() < 2 || vs[a].size() > 3)
                bad(name, "malformed header: a space direction with " + std::to_string(vs[a].size()) + " components");
            const Vec3 d{vs[a][0], vs[a][1], vs[a].size() > 2 ? vs[a][2] : 0.0};
            const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            const auto e = axis_aligned(d);
            if (!e || !(len > 0) || !std::isfinite(len))
                bad(name, "oblique or degenerate orientation: space direction of axis " + std::to_string(a) + " is (" +
                              trim(*dirs).substr(0, 120) +
                              "); only axis-aligned (possibly permuted or flipped) volumes are read — resample it");
            v.axes[a] = *e;
            v.spacing[a] = len;
        }
        if (dim == 2) {  // the normal completes a right-handed frame
            const Vec3 &x = v.axes[0], &y = v.axes[1];
            v.axes[2] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
        }
        for (int a = 0; a < 3; ++a)
            for (int c = a + 1; c < 3; ++c)
                if (v.axes[a] == v.axes[c] || (v.axes[a][0] == -v.axes[c][0] && v.axes[a][1] == -v.axes[c][1] &&
                                               v.axes[a][2] == -v.axes[c][2]))
                    bad(name, "degenerate orientation: two axes share a direction in 'space directions'");
        v.physical = true;
    } else if (const auto sps = get({"spacings"})) {
        const auto w = words(*sps);
        if (static_cast<int>(w.size()) != dim) bad(name, "malformed header: 'spacings' has the wrong number of entries");
        for (int a = 0; a < dim; ++a) {
            const double s = lower(w[a]) == "nan" ? 1.0 : number(name, "spacings", w[a]);
            if (!(s > 0) || !std::isfinite(s)) bad(name, "spacing '" + w[a] + "' is not positive and finite");
            v.spacing[a] = s;
        }
        v.physical = true;
    }
    if (const auto o = get({"space origin"})) {
        const auto ov = vector_of(name, "space origin", *o);
        if (ov.size() < 2 || ov.size() > 3) bad(name, "malformed header: 'space origin' '" + *o + "'");
        for (std::size_t c = 0; c < ov.size(); ++c) {
            if (!std::isfinite(ov[c])) bad(name, "'space origin' is not finite");
            v.origin[c] = ov[c];
        }
    }
    for (int a = 0; a < 3; ++a)
        if (!(v.spacing[a] > 1e-12 && v.spacing[a] < 1e12)) bad(name, "voxel spacing " + std::to_string(v.spacing[a]) + " is out of range");
    return v;
}

}  // namespace warpmesh
