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

// The header: the fields (lower-case names) up to the first empty line
// (attached data starts after it, at data_pos) or the end of the file.
struct Header {
    std::map<std::string, std::string> field;
    bool attached = false;
    std::size_t data_pos = 0;

    std::optional<std::string> get(std::initializer_list<const char*> keys) const {
        for (const char* k : keys)
            if (const auto it = field.find(k); it != field.end()) return it->second;
        return std::nullopt;
    }
    std::string need(const std::string& name, const char* key) const {
        const auto v = get({key});
        if (!v) bad(name, std::string("malformed header: no '") + key + "' field");
        return *v;
    }
};

Header parse_header(std::span<const std::uint8_t> bytes, const std::string& name) {
    Header h;
    std::size_t pos = 0;
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
            h.attached = true;
            break;
        }
        if (line[0] == '#') continue;
        if (line.find(":=") != std::string::npos && line.find(":=") < line.find(": ")) continue;  // key/value pair
        const std::size_t c = line.find(": ");
        if (c == std::string::npos) bad(name, "malformed header: line '" + line.substr(0, 60) + "' is not 'field: value'");
        h.field[lower(trim(line.substr(0, c)))] = trim(line.substr(c + 2));
    }
    h.data_pos = pos;
    return h;
}

enum class Encoding { raw, gzip, ascii };

// What the header says about the samples: how many, of which type and byte
// order, encoded how, after which skips.
struct Layout {
    int dim = 0;
    std::vector<std::uint64_t> sizes;
    Sample type{};
    std::size_t b = 1;      // bytes a sample
    std::uint64_t n = 0;    // samples
    Encoding encoding = Encoding::raw;
    bool swap = false;
    double byte_skip = 0;   // -1: the data ends the file (raw only)
    std::uint64_t line_skip = 0;
    std::uint64_t voxel_bytes() const { return n * b; }
};

std::uint64_t size_of(const std::string& name, const std::string& w) {
    std::uint64_t v = 0;
    for (char ch : w) {
        if (ch < '0' || ch > '9' || v > (std::uint64_t{1} << 60)) bad(name, "malformed header: size '" + w + "'");
        v = v * 10 + static_cast<std::uint64_t>(ch - '0');
    }
    return v;
}

// dimension, sizes, type, encoding, endian, skips; the voxel count checked
// against the limits (`held`: the header file's bytes, already in memory).
Layout parse_layout(const Header& h, const std::string& name, const VolumeLimits& limits, std::uint64_t held) {
    Layout L;
    const double dim_d = number(name, "dimension", h.need(name, "dimension"));
    if (dim_d != 2 && dim_d != 3)
        bad(name, "dimension " + trim(h.need(name, "dimension")) + ": only 2-D and 3-D scalar volumes are read");
    L.dim = static_cast<int>(dim_d);
    const auto size_words = words(h.need(name, "sizes"));
    if (static_cast<int>(size_words.size()) != L.dim)
        bad(name, "malformed header: 'sizes' has " + std::to_string(size_words.size()) + " entries for dimension " +
                      std::to_string(L.dim));
    for (const auto& w : size_words) L.sizes.push_back(size_of(name, w));
    const std::string type_text = h.need(name, "type");
    if (!sample_type(type_text, &L.type))
        bad(name, "unsupported type '" + type_text +
                      "' (read: 8-, 16- and 32-bit signed and unsigned integers, float, double)");
    L.b = sample_bytes(L.type);
    const std::string encoding = lower(h.need(name, "encoding"));
    if (encoding == "gzip" || encoding == "gz") L.encoding = Encoding::gzip;
    else if (encoding == "ascii" || encoding == "text" || encoding == "txt") L.encoding = Encoding::ascii;
    else if (encoding != "raw") bad(name, "unsupported encoding '" + encoding + "' (read: raw, gzip, ascii)");
    // ascii: the text is copied once more to parse it.
    L.n = checked_voxels("NRRD", name, L.sizes, L.b, limits, L.encoding == Encoding::ascii ? 2 * held : held);
    if (L.b > 1 && L.encoding != Encoding::ascii) {
        const auto endian = h.get({"endian"});
        if (!endian) bad(name, "malformed header: no 'endian' field for a " + std::to_string(L.b) + "-byte type");
        const std::string e = lower(*endian);
        if (e != "little" && e != "big") bad(name, "malformed header: endian '" + *endian + "' is not little or big");
        L.swap = (e == "little") != host_is_little_endian();
    }
    if (const auto ls = h.get({"line skip", "lineskip"})) {
        const double k = number(name, "line skip", *ls);
        if (!(k >= 0 && k <= 1e9) || k != std::floor(k)) bad(name, "malformed header: line skip '" + *ls + "'");
        L.line_skip = static_cast<std::uint64_t>(k);
    }
    if (const auto bs = h.get({"byte skip", "byteskip"})) {
        L.byte_skip = number(name, "byte skip", *bs);
        if (!(L.byte_skip >= -1 && L.byte_skip <= 1e15) || L.byte_skip != std::floor(L.byte_skip) ||
            (L.byte_skip == -1 && L.encoding != Encoding::raw))
            bad(name, "malformed header: byte skip '" + *bs + "' (-1 only with raw encoding)");
    }
    // gzip: the skipped bytes are inflated too.
    if (L.encoding == Encoding::gzip && L.byte_skip > static_cast<double>(limits.max_bytes))
        bad(name, "byte skip " + std::to_string(static_cast<std::uint64_t>(L.byte_skip)) + " of gzip data is more than " +
                      memory_limit_text(limits.max_bytes));
    return L;
}

// The largest data file the layout allows (see the file's comment), and the
// size it must at least have.
std::pair<std::uint64_t, std::uint64_t> data_file_bounds(const Layout& L) {
    const std::uint64_t skip = L.byte_skip > 0 ? static_cast<std::uint64_t>(L.byte_skip) : 0;
    const std::uint64_t lines = L.line_skip > 0 ? std::uint64_t{1} << 20 : 0;
    switch (L.encoding) {
        case Encoding::raw:
            if (L.byte_skip == -1) return {UINT64_MAX, L.voxel_bytes()};
            return {skip + L.voxel_bytes() + lines, skip + L.voxel_bytes()};
        case Encoding::gzip: {  // deflate's stored blocks: 5 bytes per 16383, plus headers and members
            const std::uint64_t raw = skip + L.voxel_bytes();
            return {raw + raw / 16383 * 5 + 5 + lines + (std::uint64_t{1} << 20), 0};
        }
        case Encoding::ascii: return {64 * L.n + lines + (std::uint64_t{1} << 20), 0};
    }
    return {0, 0};
}

// The detached data file `path`, read no further than the layout implies: a
// regular file (not a device, not a FIFO) of a size the layout allows.  With
// byte skip -1 only its last voxel bytes are read.
std::vector<std::uint8_t> read_data_file(const std::string& name, const std::string& path, const Layout& L,
                                         const VolumeLimits& limits) {
    namespace fs = std::filesystem;
    const std::string prefix = "NRRD '" + name + "': data file '" + path + "'";
    std::error_code ec;
    const auto type = fs::status(path, ec).type();
    if (type == fs::file_type::regular) {
        const std::uint64_t size = fs::file_size(path, ec);
        const auto [most, least] = data_file_bounds(L);
        if (!ec && size < least)
            throw InputError(prefix + ": truncated: it has " + std::to_string(size) + " bytes, the header implies " +
                             std::to_string(least) + " (byte skip and voxels)");
        if (!ec && size > most)
            throw InputError(prefix + ": it has " + std::to_string(size) + " bytes, more than the " + std::to_string(most) +
                             " the header allows (sizes, type and encoding): the wrong data file?");
        if (L.encoding == Encoding::raw && L.byte_skip == -1 && !ec) {
            std::ifstream in(path, std::ios::binary);
            std::vector<std::uint8_t> tail(static_cast<std::size_t>(L.voxel_bytes()));
            in.seekg(static_cast<std::streamoff>(size - L.voxel_bytes()));
            in.read(reinterpret_cast<char*>(tail.data()), static_cast<std::streamsize>(tail.size()));
            if (!in) throw InputError(prefix + ": read error");
            return tail;
        }
        return read_regular_file(prefix, path, std::min(most, limits.max_bytes), memory_limit_text(limits.max_bytes));
    }
    return read_regular_file(prefix, path, 0, "");  // refuses with the reason (missing, directory, device, FIFO)
}

// The data bytes: after the header (attached), or the detached data file,
// then after `line skip` lines.  `own` keeps a data file's bytes.
std::span<const std::uint8_t> data_bytes(std::span<const std::uint8_t> bytes, const Header& h, const Layout& L,
                                         const std::string& name, const std::string& dir, const VolumeLimits& limits,
                                         std::vector<std::uint8_t>& own) {
    std::span<const std::uint8_t> data;
    if (const auto file = h.get({"data file", "datafile"})) {
        const auto w = words(*file);
        if (w.size() != 1 || w[0] == "LIST" || file->find('%') != std::string::npos)
            bad(name, "'data file: " + *file + "': only a single detached data file is read");
        if (dir.empty()) bad(name, "detached data file '" + *file + "' cannot be read from memory");
        std::filesystem::path p(*file);
        if (p.is_relative()) p = std::filesystem::path(dir) / p;
        own = read_data_file(name, p.string(), L, limits);
        // Held at once: the header file, the data file, any inflated data
        // (or ascii's copy) and the doubles.
        const std::uint64_t inflated = L.encoding == Encoding::raw ? 0
                                       : L.encoding == Encoding::gzip ? static_cast<std::uint64_t>(L.byte_skip) + L.voxel_bytes()
                                                                      : own.size();
        const std::uint64_t held = bytes.size() + own.size() + inflated + 8 * L.n;
        if (held > limits.max_bytes)
            bad(name, "reading data file '" + p.string() + "' needs about " + std::to_string(held >> 20) +
                          " MB, more than " + memory_limit_text(limits.max_bytes));
        data = own;
        if (L.byte_skip == -1) return data;  // the file's last voxel bytes: lines and skip are before them
    } else {
        if (!h.attached) bad(name, "truncated: the header has no blank line and no 'data file', so there is no data");
        data = bytes.subspan(h.data_pos);
    }
    for (std::uint64_t q = 0; q < L.line_skip; ++q) {
        std::size_t e = 0;
        while (e < data.size() && data[e] != '\n') ++e;
        if (e == data.size()) bad(name, "truncated data: fewer lines than 'line skip' " + std::to_string(L.line_skip));
        data = data.subspan(e + 1);
    }
    return data;
}

std::vector<double> decode_ascii(std::span<const std::uint8_t> data, const Layout& L, const std::string& name,
                                 bool* integer) {
    if (L.byte_skip > 0) data = data.subspan(std::min<std::size_t>(data.size(), static_cast<std::size_t>(L.byte_skip)));
    const std::string text(reinterpret_cast<const char*>(data.data()), data.size());
    std::vector<double> values;
    values.reserve(std::min<std::size_t>(L.n, text.size() / 2 + 1));
    const char* p = text.c_str();
    while (values.size() < L.n) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
        if (!*p) break;
        char* end = nullptr;
        const double x = std::strtod(p, &end);
        if (end == p || !std::isfinite(x)) bad(name, "malformed ascii data at value " + std::to_string(values.size()));
        values.push_back(x);
        p = end;
    }
    if (values.size() < L.n)
        bad(name, "truncated data: expected " + std::to_string(L.n) + " values, found " + std::to_string(values.size()));
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == ',') ++p;
    if (*p) bad(name, "more ascii data than the " + std::to_string(L.n) + " values the header implies (sizes): a wrong header?");
    *integer = true;
    for (double x : values) *integer = *integer && x == std::floor(x);
    return values;
}

// Raw or gzip samples into v (decode_samples): gzip inflated up to byte skip
// + the voxel bytes (more is an error), then the skip applied — 16-bit
// samples without a skip straight into v.labels' memory and decoded there,
// so that the file's inflated bytes are never held beside their labels; raw:
// the skip (or, -1, the last voxel bytes).
void decode_binary(std::span<const std::uint8_t> data, const Layout& L, const std::string& name, Volume& v) {
    const std::uint64_t need = L.voxel_bytes();
    std::vector<std::uint8_t> inflated;
    if (L.encoding == Encoding::gzip && L.byte_skip == 0 && (L.type == Sample::i16 || L.type == Sample::u16)) {
        if (static_cast<double>(data.size()) * 1032.0 + 1024 < static_cast<double>(need))
            bad(name, "truncated data: " + std::to_string(data.size()) + " gzip bytes cannot hold " + std::to_string(need) +
                          " bytes of voxels");
        v.labels.resize(static_cast<std::size_t>(L.n));
        const std::span<std::uint8_t> bytes(reinterpret_cast<std::uint8_t*>(v.labels.data()), static_cast<std::size_t>(need));
        const std::size_t got = gunzip_exact_into(data, bytes, name);
        if (got < need)
            bad(name, "truncated data: gzip data inflates to " + std::to_string(got) + " bytes, expected " + std::to_string(need));
        return decode_samples("NRRD", name, bytes, L.type, L.swap, L.n, v);
    }
    if (L.encoding == Encoding::gzip) {
        // deflate cannot compress more than about 1032:1: refuse data that
        // is too short to hold the voxels before inflating anything.
        if (static_cast<double>(data.size()) * 1032.0 + 1024 < static_cast<double>(need))
            bad(name, "truncated data: " + std::to_string(data.size()) + " gzip bytes cannot hold " + std::to_string(need) +
                          " bytes of voxels");
        const std::uint64_t skip = static_cast<std::uint64_t>(L.byte_skip);
        inflated = gunzip_exact(data, static_cast<std::size_t>(need + skip), name);
        if (inflated.size() < need + skip)
            bad(name, "truncated data: gzip data inflates to " + std::to_string(inflated.size()) + " bytes, expected " +
                          std::to_string(need + skip));
        data = std::span<const std::uint8_t>(inflated).subspan(static_cast<std::size_t>(skip));
    } else if (L.byte_skip == -1) {
        if (data.size() < need)
            bad(name, "truncated data: expected " + std::to_string(need) + " bytes, found " + std::to_string(data.size()));
        data = data.subspan(data.size() - need);
    } else {
        if (L.byte_skip > static_cast<double>(data.size())) bad(name, "truncated data: byte skip beyond the end of the data");
        data = data.subspan(static_cast<std::size_t>(L.byte_skip));
        if (data.size() < need)
            bad(name, "truncated data: expected " + std::to_string(need) + " bytes of voxels, found " +
                          std::to_string(data.size()));
        // More: the sizes or the type do not describe the data (with byte
        // skip -1 the voxels are the last bytes, by definition).
        if (data.size() > need)
            bad(name, "the data has " + std::to_string(data.size()) + " bytes, more than the " + std::to_string(need) +
                          " bytes of voxels the header implies (sizes and type): a wrong header?");
    }
    decode_samples("NRRD", name, data, L.type, L.swap, L.n, v);
}

// `space directions`: each index axis's spacing and direction.
void read_directions(const std::string& dirs, const std::string& name, int dim, Volume& v) {
    const auto vs = vectors_of(name, "space directions", dirs);
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
                          trim(dirs).substr(0, 120) +
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
            if (v.axes[a] == v.axes[c] ||
                (v.axes[a][0] == -v.axes[c][0] && v.axes[a][1] == -v.axes[c][1] && v.axes[a][2] == -v.axes[c][2]))
                bad(name, "degenerate orientation: two axes share a direction in 'space directions'");
    v.physical = true;
}

// `spacings`: numbers (physical, mm), or all `nan` (unknown: pixels).  A mix
// is refused: a volume meshed in mm needs every spacing.
void read_spacings(const std::string& sps, const std::string& name, int dim, Volume& v) {
    const auto w = words(sps);
    if (static_cast<int>(w.size()) != dim) bad(name, "malformed header: 'spacings' has the wrong number of entries");
    int unknown = 0;
    for (const auto& x : w) unknown += lower(x) == "nan";
    if (unknown == dim) return;  // no physical size: pixels, as a TIFF (--pixel-size gives one)
    for (int a = 0; a < dim; ++a) {
        if (lower(w[a]) == "nan")
            bad(name, "'spacings: " + trim(sps) + "': axis " + std::to_string(a) +
                          " has no spacing (nan) while others have one; give every axis a spacing, or none (all nan: "
                          "the volume is read in pixels, and --pixel-size sets a size)");
        const double s = number(name, "spacings", w[a]);
        if (!(s > 0) || !std::isfinite(s)) bad(name, "spacing '" + w[a] + "' is not positive and finite");
        v.spacing[a] = s;
    }
    v.physical = true;
}

void read_geometry(const Header& h, const std::string& name, int dim, Volume& v) {
    if (const auto sp = h.get({"space"})) v.space = *sp;
    if (const auto dirs = h.get({"space directions"})) read_directions(*dirs, name, dim, v);
    else if (const auto sps = h.get({"spacings"})) read_spacings(*sps, name, dim, v);
    if (const auto o = h.get({"space origin"})) {
        const auto ov = vector_of(name, "space origin", *o);
        if (ov.size() < 2 || ov.size() > 3) bad(name, "malformed header: 'space origin' '" + *o + "'");
        for (std::size_t c = 0; c < ov.size(); ++c) {
            if (!std::isfinite(ov[c])) bad(name, "'space origin' is not finite");
            v.origin[c] = ov[c];
        }
    }
    for (int a = 0; a < 3; ++a)
        if (!(v.spacing[a] > 1e-12 && v.spacing[a] < 1e12))
            bad(name, "voxel spacing " + std::to_string(v.spacing[a]) + " is out of range");
}

}  // namespace

Volume decode_nrrd(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits,
                   const std::string& dir) {
    const Header h = parse_header(bytes, name);
    const Layout L = parse_layout(h, name, limits, bytes.size());
    std::vector<std::uint8_t> own;
    const std::span<const std::uint8_t> data = data_bytes(bytes, h, L, name, dir, limits, own);
    Volume v;
    v.format = "NRRD";
    v.source = name;
    if (L.encoding == Encoding::ascii) v.values = decode_ascii(data, L, name, &v.integer_valued);
    else decode_binary(data, L, name, v);
    for (int a = 0; a < 3; ++a) v.dims[a] = a < L.dim ? static_cast<std::int64_t>(L.sizes[a]) : 1;
    read_geometry(h, name, L.dim, v);
    return v;
}

}  // namespace warpmesh
