#define BOOST_TEST_MODULE writers
#include <boost/test/unit_test.hpp>

#include "fixture_meshes.hpp"
#include "support.hpp"

// Writers round-trip: small hand-built meshes are written in every format to a
// temporary directory, read back with the small readers below and compared
// with the original.  Also: the dispatcher, atomic-write failures, and the
// quality report on hand-computed triangles.

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/io/writers.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;
using warpmesh::testing::grid_mesh;
using warpmesh::testing::two_region_mesh;

namespace {

// ---- fixtures ------------------------------------------------------------------

struct TempDir : warpmesh::testing::TempDir {
    TempDir() : warpmesh::testing::TempDir("warpmesh-writers") {}
    // The names of the files in it, sorted (hides the base's count).
    std::vector<std::string> entries() const {
        std::vector<std::string> r;
        for (const auto& e : fs::directory_iterator(path)) r.push_back(e.path().filename().string());
        std::sort(r.begin(), r.end());
        return r;
    }
};

// The unit square split along its diagonal (0,0)-(1,1); bottom and left are
// lattice border, right and top level set.
Mesh square_mesh() {
    Mesh m;
    m.vertices = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.region = {1, 1};
    m.boundary = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    m.boundary_tag = {2, 1, 1, 2};
    return m;
}

using warpmesh::testing::slurp;

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::max(std::abs(a), std::abs(b))); }

void check_vertices(const Mesh& m, const std::vector<Vec2>& got) {
    BOOST_REQUIRE_EQUAL(got.size(), m.vertices.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        BOOST_TEST(close(got[i].x, m.vertices[i].x), "vertex " << i << " x " << got[i].x << " vs " << m.vertices[i].x);
        BOOST_TEST(close(got[i].y, m.vertices[i].y), "vertex " << i << " y " << got[i].y << " vs " << m.vertices[i].y);
    }
}

// A minimal XML well-formedness check: every start tag is closed in order,
// attributes are quoted, comments/declarations skipped.
bool xml_balanced(const std::string& s, std::string& why) {
    std::vector<std::string> stack;
    std::size_t i = 0;
    while ((i = s.find('<', i)) != std::string::npos) {
        if (s.compare(i, 9, "<![CDATA[") == 0) {
            i = s.find("]]>", i);
            if (i == std::string::npos) return why = "open CDATA", false;
            continue;
        }
        if (s.compare(i, 4, "<!--") == 0) {
            i = s.find("-->", i);
            if (i == std::string::npos) return why = "open comment", false;
            continue;
        }
        const std::size_t end = s.find('>', i);
        if (end == std::string::npos) return why = "unterminated tag", false;
        std::string tag = s.substr(i + 1, end - i - 1);
        i = end + 1;
        if (tag.empty()) return why = "empty tag", false;
        if (tag[0] == '?' || tag[0] == '!') continue;
        if (std::count(tag.begin(), tag.end(), '"') % 2) return why = "odd quotes in <" + tag + ">", false;
        if (tag.find('<') != std::string::npos) return why = "'<' inside a tag", false;
        if (tag[0] == '/') {
            const std::string name = tag.substr(1);
            if (stack.empty() || stack.back() != name) return why = "mismatched </" + name + ">", false;
            stack.pop_back();
        } else if (tag.back() != '/') {
            stack.push_back(tag.substr(0, tag.find_first_of(" \t\n")));
        }
    }
    if (!stack.empty()) return why = "unclosed <" + stack.back() + ">", false;
    return true;
}

bool have_python3() { return std::system("python3 -c 'import xml.dom.minidom, json' >/dev/null 2>&1") == 0; }
bool python_ok(const std::string& code, const std::string& arg) {
    const std::string cmd = "python3 -c '" + code + "' '" + arg + "' >/dev/null 2>&1";
    return std::system(cmd.c_str()) == 0;
}

// ---- VTU reader ----------------------------------------------------------------

std::string xml_attr(const std::string& s, std::size_t from, const std::string& name) {
    const std::size_t p = s.find(" " + name + "=\"", from);
    BOOST_REQUIRE(p != std::string::npos);
    const std::size_t b = p + name.size() + 3;
    return s.substr(b, s.find('"', b) - b);
}

// The whitespace-separated values of the DataArray with this Name attribute.
std::vector<std::string> vtu_array(const std::string& s, const std::string& name, std::string* type = nullptr) {
    const std::size_t p = s.find("Name=\"" + name + "\"");
    BOOST_REQUIRE_MESSAGE(p != std::string::npos, "no DataArray " << name);
    const std::size_t open = s.rfind("<DataArray", p);
    if (type) *type = xml_attr(s, open, "type");
    const std::size_t b = s.find('>', p) + 1, e = s.find("</DataArray>", b);
    std::istringstream in(s.substr(b, e - b));
    std::vector<std::string> r;
    for (std::string w; in >> w;) r.push_back(w);
    return r;
}

void check_vtu(const Mesh& m, const std::string& path) {
    const std::string s = slurp(path);
    std::string why;
    BOOST_TEST(xml_balanced(s, why), why);
    BOOST_TEST(s.find("type=\"UnstructuredGrid\"") != std::string::npos);
    BOOST_TEST(std::stoul(xml_attr(s, 0, "NumberOfPoints")) == m.vertices.size());
    BOOST_TEST(std::stoul(xml_attr(s, 0, "NumberOfCells")) == m.triangles.size());
    const auto pts = vtu_array(s, "Points");
    BOOST_REQUIRE_EQUAL(pts.size(), 3 * m.vertices.size());
    std::vector<Vec2> v;
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
        v.push_back({std::stod(pts[3 * i]), std::stod(pts[3 * i + 1])});
        BOOST_TEST(std::stod(pts[3 * i + 2]) == 0.0);
    }
    check_vertices(m, v);
    const auto conn = vtu_array(s, "connectivity"), off = vtu_array(s, "offsets"), types = vtu_array(s, "types");
    BOOST_REQUIRE_EQUAL(conn.size(), 3 * m.triangles.size());
    BOOST_REQUIRE_EQUAL(off.size(), m.triangles.size());
    BOOST_REQUIRE_EQUAL(types.size(), m.triangles.size());
    for (std::size_t k = 0; k < m.triangles.size(); ++k) {
        for (int c = 0; c < 3; ++c) BOOST_TEST(std::stoi(conn[3 * k + c]) == m.triangles[k][c]);
        BOOST_TEST(std::stoul(off[k]) == 3 * (k + 1));
        BOOST_TEST(types[k] == "5");
    }
    std::string type;
    const auto region = vtu_array(s, "region", &type);
    BOOST_TEST(type == "Int32");
    BOOST_REQUIRE_EQUAL(region.size(), m.triangles.size());
    for (std::size_t k = 0; k < region.size(); ++k) BOOST_TEST(std::stoi(region[k]) == m.region[k]);
    for (const auto& [name, values] : m.cell_data) {
        std::string escaped;
        for (char c : name)
            escaped += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : c == '"' ? "&quot;" : std::string(1, c);
        const auto got = vtu_array(s, escaped, &type);
        BOOST_TEST(type == "Float64");
        BOOST_REQUIRE_EQUAL(got.size(), values.size());
        for (std::size_t k = 0; k < got.size(); ++k) BOOST_TEST(close(std::stod(got[k]), values[k]));
    }
}

// ---- MSH 4.1 reader ------------------------------------------------------------

struct Msh {
    std::string format;
    std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) → name
    std::map<std::pair<int, int>, std::vector<int>> entity_physicals;  // (dim, entity) → physical tags
    std::map<long, Vec2> nodes;
    struct Element {
        int dim, entity, type;
        std::vector<long> nodes;
    };
    std::map<long, Element> elements;
    std::map<std::string, std::map<long, double>> element_data;
};

Msh read_msh(const std::string& path) {
    std::istringstream in(slurp(path));
    Msh m;
    std::string section;
    auto expect_end = [&](const std::string& name) {
        std::string end;
        in >> end;
        BOOST_REQUIRE_EQUAL(end, "$End" + name);
    };
    auto quoted = [&]() {
        std::string s;
        in >> std::ws;
        std::getline(in, s);
        BOOST_REQUIRE(s.size() >= 2 && s.front() == '"' && s.back() == '"');
        return s.substr(1, s.size() - 2);
    };
    while (in >> section) {
        BOOST_REQUIRE(section[0] == '$');
        const std::string name = section.substr(1);
        if (name == "MeshFormat") {
            std::string v, file_type, size;
            in >> v >> file_type >> size;
            m.format = v + " " + file_type + " " + size;
        } else if (name == "PhysicalNames") {
            int n;
            in >> n;
            for (int i = 0; i < n; ++i) {
                int dim, tag;
                in >> dim >> tag;
                m.physical_names[{dim, tag}] = quoted();
            }
        } else if (name == "Entities") {
            std::array<std::size_t, 4> count;
            in >> count[0] >> count[1] >> count[2] >> count[3];
            for (int dim = 0; dim < 4; ++dim)
                for (std::size_t i = 0; i < count[static_cast<std::size_t>(dim)]; ++i) {
                    int tag;
                    double bb;
                    in >> tag;
                    for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in >> bb;
                    std::size_t nphys;
                    in >> nphys;
                    std::vector<int> phys(nphys);
                    for (auto& p : phys) in >> p;
                    m.entity_physicals[{dim, tag}] = phys;
                    if (dim > 0) {
                        std::size_t nbound;
                        in >> nbound;
                        for (std::size_t b = 0; b < nbound; ++b) in >> tag;
                    }
                }
        } else if (name == "Nodes") {
            std::size_t blocks, total;
            long min_tag, max_tag;
            in >> blocks >> total >> min_tag >> max_tag;
            for (std::size_t b = 0; b < blocks; ++b) {
                int dim, entity, parametric;
                std::size_t n;
                in >> dim >> entity >> parametric >> n;
                BOOST_REQUIRE_EQUAL(parametric, 0);
                std::vector<long> tags(n);
                for (auto& t : tags) in >> t;
                for (const long t : tags) {
                    double x, y, z;
                    in >> x >> y >> z;
                    BOOST_TEST(z == 0.0);
                    m.nodes[t] = {x, y};
                }
            }
            BOOST_TEST(m.nodes.size() == total);
            if (total) BOOST_TEST((m.nodes.begin()->first == min_tag && m.nodes.rbegin()->first == max_tag));
        } else if (name == "Elements") {
            std::size_t blocks, total;
            long min_tag, max_tag;
            in >> blocks >> total >> min_tag >> max_tag;
            for (std::size_t b = 0; b < blocks; ++b) {
                int dim, entity, type;
                std::size_t n;
                in >> dim >> entity >> type >> n;
                const int nn = type == 2 ? 3 : type == 1 ? 2 : -1;
                BOOST_REQUIRE(nn > 0);
                for (std::size_t e = 0; e < n; ++e) {
                    long tag;
                    in >> tag;
                    Msh::Element el{dim, entity, type, std::vector<long>(static_cast<std::size_t>(nn))};
                    for (auto& v : el.nodes) in >> v;
                    BOOST_TEST(m.elements.count(tag) == 0u);
                    m.elements[tag] = el;
                }
            }
            BOOST_TEST(m.elements.size() == total);
            if (total) BOOST_TEST((m.elements.begin()->first == min_tag && m.elements.rbegin()->first == max_tag));
        } else if (name == "ElementData") {
            int nstr, nreal, nint;
            in >> nstr;
            BOOST_REQUIRE_EQUAL(nstr, 1);
            const std::string view = quoted();
            in >> nreal;
            double time;
            for (int i = 0; i < nreal; ++i) in >> time;
            in >> nint;
            BOOST_REQUIRE(nint >= 3);
            std::vector<long> ints(static_cast<std::size_t>(nint));
            for (auto& v : ints) in >> v;
            BOOST_TEST(ints[1] == 1);  // one component
            for (long i = 0; i < ints[2]; ++i) {
                long tag;
                std::string value;  // "nan" on lines: istream >> double refuses it
                in >> tag >> value;
                m.element_data[view][tag] = std::strtod(value.c_str(), nullptr);
            }
        } else {
            BOOST_FAIL("unexpected section " << section);
        }
        BOOST_REQUIRE(in);
        expect_end(name);
    }
    return m;
}

// The expected name of region `tag` (detail::region_name's rule, restated).
std::string expected_region_name(const Mesh& mesh, std::int32_t tag) {
    for (const auto& [t, name] : mesh.region_names)
        if (t == tag) return name;
    const std::set<std::int32_t> regions(mesh.region.begin(), mesh.region.end());
    return regions.size() == 1 ? "domain" : "domain_" + std::to_string(tag);
}

void check_msh(const Mesh& mesh, const std::string& path, bool with_cell_data) {
    const Msh m = read_msh(path);
    BOOST_TEST(m.format == "4.1 0 8");
    std::vector<Vec2> v;
    for (long t = 1; t <= static_cast<long>(mesh.vertices.size()); ++t) {
        BOOST_REQUIRE(m.nodes.count(t));
        v.push_back(m.nodes.at(t));
    }
    check_vertices(mesh, v);

    const std::size_t nt = mesh.triangles.size();
    const std::size_t ne = nt + mesh.boundary.size() + mesh.interfaces.size();
    BOOST_REQUIRE_EQUAL(m.elements.size(), ne);
    for (std::size_t k = 0; k < nt; ++k) {
        const auto& e = m.elements.at(static_cast<long>(k + 1));
        BOOST_TEST(e.type == 2);
        BOOST_TEST(e.dim == 2);
        for (int c = 0; c < 3; ++c) BOOST_TEST(e.nodes[static_cast<std::size_t>(c)] == mesh.triangles[k][c] + 1);
        // The triangle's surface entity carries one physical group whose name
        // identifies the region.
        const auto& phys = m.entity_physicals.at({2, e.entity});
        BOOST_REQUIRE_EQUAL(phys.size(), 1u);
        BOOST_TEST(m.physical_names.at({2, phys[0]}) == expected_region_name(mesh, mesh.region[k]));
    }
    for (std::size_t k = 0; k < mesh.boundary.size(); ++k) {
        const auto& e = m.elements.at(static_cast<long>(nt + k + 1));
        BOOST_TEST(e.type == 1);
        BOOST_TEST(e.dim == 1);
        BOOST_TEST(e.nodes[0] == mesh.boundary[k][0] + 1);
        BOOST_TEST(e.nodes[1] == mesh.boundary[k][1] + 1);
        const auto& phys = m.entity_physicals.at({1, e.entity});
        BOOST_REQUIRE_EQUAL(phys.size(), 1u);
        const std::int32_t tag = mesh.boundary_tag[k];
        BOOST_TEST(phys[0] == tag);
        BOOST_TEST(m.physical_names.at({1, phys[0]}) == (tag == 1 ? "boundary" : "domain_border"));
    }
    // Interface edges: tags after the boundary's, region 3 on the left.
    for (std::size_t k = 0; k < mesh.interfaces.size(); ++k) {
        const auto& e = m.elements.at(static_cast<long>(nt + mesh.boundary.size() + k + 1));
        BOOST_TEST(e.type == 1);
        const auto& phys = m.entity_physicals.at({1, e.entity});
        BOOST_REQUIRE_EQUAL(phys.size(), 1u);
        BOOST_TEST(phys[0] == 3);
        BOOST_TEST(m.physical_names.at({1, 3}) == "interface_3_8");
        const auto& i = mesh.interfaces[k];
        const bool flipped = mesh.interface_regions[k][0] != 3;
        BOOST_TEST(e.nodes[0] == (flipped ? i[1] : i[0]) + 1);
        BOOST_TEST(e.nodes[1] == (flipped ? i[0] : i[1]) + 1);
    }
    // Cell data only when asked, then for every element (nan on the lines).
    BOOST_REQUIRE_EQUAL(m.element_data.size(), with_cell_data ? mesh.cell_data.size() : 0u);
    if (!with_cell_data) return;
    for (const auto& [name, values] : mesh.cell_data) {
        std::string sanitized = name;  // '"' cannot appear inside an MSH string
        std::replace(sanitized.begin(), sanitized.end(), '"', '\'');
        BOOST_REQUIRE(m.element_data.count(sanitized));
        const auto& got = m.element_data.at(sanitized);
        BOOST_REQUIRE_EQUAL(got.size(), ne);
        for (std::size_t k = 0; k < nt; ++k) BOOST_TEST(close(got.at(static_cast<long>(k + 1)), values[k]));
        for (std::size_t k = nt; k < ne; ++k) BOOST_TEST(std::isnan(got.at(static_cast<long>(k + 1))));
    }
}

// ---- Triangle reader -----------------------------------------------------------

void check_triangle(const Mesh& mesh, const std::string& stem) {
    std::istringstream node(slurp(stem + ".node")), ele(slurp(stem + ".ele")), poly(slurp(stem + ".poly"));
    std::size_t n, dim, attrs, markers;
    node >> n >> dim >> attrs >> markers;
    BOOST_REQUIRE_EQUAL(n, mesh.vertices.size());
    BOOST_TEST(dim == 2u);
    BOOST_TEST(attrs == 0u);
    BOOST_TEST(markers == 1u);
    // Expected marker: smallest boundary tag at the vertex, else 3 on an
    // interface (the fixtures' boundary tags are 1 and 2), else 0.
    std::map<std::int32_t, int> marker;
    for (const auto& e : mesh.interfaces) marker[e[0]] = marker[e[1]] = 3;
    for (std::size_t k = 0; k < mesh.boundary.size(); ++k)
        for (const std::int32_t v : mesh.boundary[k]) {
            const bool on_boundary_before = marker.count(v) && marker[v] < 3;
            marker[v] = on_boundary_before ? std::min(marker[v], mesh.boundary_tag[k]) : mesh.boundary_tag[k];
        }
    std::vector<Vec2> v;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t id;
        double x, y;
        int got_marker;
        node >> id >> x >> y >> got_marker;
        BOOST_TEST(id == i + 1);
        const auto it = marker.find(static_cast<std::int32_t>(i));
        BOOST_TEST(got_marker == (it == marker.end() ? 0 : it->second), "vertex " << i);
        v.push_back({x, y});
    }
    BOOST_REQUIRE(node);
    check_vertices(mesh, v);

    std::size_t t, per, eattrs;
    ele >> t >> per >> eattrs;
    BOOST_REQUIRE_EQUAL(t, mesh.triangles.size());
    BOOST_TEST(per == 3u);
    BOOST_TEST(eattrs == 1u);
    for (std::size_t k = 0; k < t; ++k) {
        std::size_t id;
        std::int64_t a, b, c;
        double region;
        ele >> id >> a >> b >> c >> region;
        BOOST_TEST(id == k + 1);
        BOOST_TEST(a == mesh.triangles[k][0] + 1);
        BOOST_TEST(b == mesh.triangles[k][1] + 1);
        BOOST_TEST(c == mesh.triangles[k][2] + 1);
        BOOST_TEST(region == static_cast<double>(mesh.region[k]));
    }
    BOOST_REQUIRE(ele);

    std::size_t pv, pdim, pattrs, pmarkers, segs, smarkers;
    poly >> pv >> pdim >> pattrs >> pmarkers >> segs >> smarkers;
    BOOST_TEST(pv == 0u);
    BOOST_REQUIRE_EQUAL(segs, mesh.boundary.size() + mesh.interfaces.size());
    BOOST_TEST(smarkers == 1u);
    for (std::size_t k = 0; k < segs; ++k) {
        std::size_t id;
        std::int64_t a, b;
        int tag;
        poly >> id >> a >> b >> tag;
        const bool boundary = k < mesh.boundary.size();
        const auto& e = boundary ? mesh.boundary[k] : mesh.interfaces[k - mesh.boundary.size()];
        BOOST_TEST(a == e[0] + 1);
        BOOST_TEST(b == e[1] + 1);
        BOOST_TEST(tag == (boundary ? mesh.boundary_tag[k] : 3));
    }
    std::size_t holes = 99;
    poly >> holes;
    BOOST_TEST(holes == 0u);
}

// ---- SVG check -----------------------------------------------------------------

std::size_t count(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
    return n;
}

void check_svg(const Mesh& mesh, const std::string& path, bool coloured) {
    const std::string s = slurp(path);
    std::string why;
    BOOST_TEST(xml_balanced(s, why), why);
    BOOST_TEST(s.find("<svg xmlns=\"http://www.w3.org/2000/svg\"") != std::string::npos);
    BOOST_TEST(count(s, "<polygon") == mesh.triangles.size());
    std::set<std::int32_t> tags(mesh.boundary_tag.begin(), mesh.boundary_tag.end());
    BOOST_TEST(count(s, "<path class=\"boundary-") == tags.size());
    BOOST_TEST((s.find("id=\"legend\"") != std::string::npos) == coloured);
    // y is flipped: the first triangle's highest vertex has the smallest SVG y.
    const std::size_t p = s.find("<polygon points=\"") + 17;
    std::istringstream pts(s.substr(p, s.find('"', p) - p));
    std::vector<std::pair<double, double>> xy;
    for (std::string w; pts >> w;) xy.push_back({std::stod(w), std::stod(w.substr(w.find(',') + 1))});
    BOOST_REQUIRE_EQUAL(xy.size(), 3u);
    const auto& t = mesh.triangles[0];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double my = mesh.vertices[static_cast<std::size_t>(t[i])].y - mesh.vertices[static_cast<std::size_t>(t[j])].y;
            if (my > 1e-9) BOOST_TEST(xy[static_cast<std::size_t>(i)].second < xy[static_cast<std::size_t>(j)].second);
            const double mx = mesh.vertices[static_cast<std::size_t>(t[i])].x - mesh.vertices[static_cast<std::size_t>(t[j])].x;
            if (mx > 1e-9) BOOST_TEST(xy[static_cast<std::size_t>(i)].first > xy[static_cast<std::size_t>(j)].first);
        }
}

// ---- Abaqus .inp check ----------------------------------------------------------

// The "*KEYWORD, params" header lines of `s` with the comma-separated ids
// (or words) of their data lines.
std::vector<std::pair<std::string, std::vector<std::string>>> inp_blocks(const std::string& s) {
    std::vector<std::pair<std::string, std::vector<std::string>>> blocks;
    std::istringstream in(s);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("**", 0) == 0) continue;
        if (line.rfind("*", 0) == 0) {
            blocks.push_back({line, {}});
            continue;
        }
        BOOST_REQUIRE(!blocks.empty());
        std::istringstream fields(line);
        for (std::string f; std::getline(fields, f, ',');) {
            f.erase(0, f.find_first_not_of(' '));
            blocks.back().second.push_back(f);
        }
    }
    return blocks;
}

void check_inp(const Mesh& mesh, const std::string& path) {
    const auto blocks = inp_blocks(slurp(path));
    std::map<std::string, std::vector<std::string>> by_header(blocks.begin(), blocks.end());
    BOOST_REQUIRE(by_header.count("*NODE"));
    const auto& nodes = by_header["*NODE"];
    BOOST_REQUIRE_EQUAL(nodes.size(), 3 * mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int c = 1; c <= 2; ++c) {
            // CalculiX reads numbers of at most 20 characters.
            const std::string& f = nodes[3 * i + static_cast<std::size_t>(c)];
            BOOST_TEST(f.size() <= 20u, f);
            const double want = c == 1 ? mesh.vertices[i].x : mesh.vertices[i].y;
            BOOST_TEST(std::abs(std::stod(f) - want) <= 5e-14 * std::abs(want), f << " vs " << want);
        }
    BOOST_REQUIRE(by_header.count("*ELEMENT, TYPE=CPS3"));
    const auto& el = by_header["*ELEMENT, TYPE=CPS3"];
    BOOST_REQUIRE_EQUAL(el.size(), 4 * mesh.triangles.size());
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
        for (int c = 0; c < 3; ++c) BOOST_TEST(std::stol(el[4 * k + 1 + static_cast<std::size_t>(c)]) == mesh.triangles[k][c] + 1);
    // One element set per region, named like the .msh groups (Abaqus-safe).
    for (const std::int32_t tag : std::set<std::int32_t>(mesh.region.begin(), mesh.region.end())) {
        std::string name = expected_region_name(mesh, tag);
        std::replace(name.begin(), name.end(), ' ', '_');
        const std::string header = "*ELSET, ELSET=" + name;
        BOOST_REQUIRE_MESSAGE(by_header.count(header), "no " << header);
        std::vector<std::string> expect;
        for (std::size_t k = 0; k < mesh.region.size(); ++k)
            if (mesh.region[k] == tag) expect.push_back(std::to_string(k + 1));
        BOOST_TEST(by_header[header] == expect, boost::test_tools::per_element());
    }
    // Surfaces: as many element faces as edges, each face's side is the edge.
    std::map<std::string, std::size_t> edges{{"boundary", 0}, {"domain_border", 0}};
    for (const std::int32_t t : mesh.boundary_tag) ++edges[t == 1 ? "boundary" : "domain_border"];
    if (!mesh.interfaces.empty()) edges["interface_3_8"] = mesh.interfaces.size();
    for (const auto& [name, n] : edges) {
        if (n == 0) continue;
        BOOST_REQUIRE_MESSAGE(by_header.count("*SURFACE, TYPE=ELEMENT, NAME=" + name), "no surface " << name);
        BOOST_TEST(by_header.count("*NSET, NSET=" + name) == 1u);
        std::size_t faces = 0;
        for (int side = 1; side <= 3; ++side) {
            const std::string set = "_" + name + "_S" + std::to_string(side);
            if (!by_header.count("*ELSET, ELSET=" + set)) continue;
            faces += by_header["*ELSET, ELSET=" + set].size();
        }
        BOOST_TEST(faces == n, name);
    }
}

void round_trip(const Mesh& mesh, const std::string& label) {
    TempDir dir;
    // The readers below parse text: every format as ASCII.  The binary forms
    // are read by the real clients (tests/python/test_solver_formats.py).
    WriteOptions text;
    text.ascii = true;
    write_mesh(mesh, dir.file(label + ".vtu"), text);
    write_mesh(mesh, dir.file(label + ".msh"), text);
    WriteOptions with_data = text;
    with_data.msh.cell_data = true;
    write_mesh(mesh, dir.file(label + "-data.msh"), with_data);
    write_mesh(mesh, dir.file(label + ".xdmf"), text);
    write_mesh(mesh, dir.file(label + ".inp"), {});
    write_mesh(mesh, dir.file(label + ".ele"), {});
    write_mesh(mesh, dir.file(label + ".svg"), {});
    WriteOptions coloured;
    coloured.svg.color_by_min_angle = true;
    write_mesh(mesh, dir.file(label + "-angle.svg"), coloured);
    BOOST_TEST(dir.entries() == (std::vector<std::string>{label + "-angle.svg", label + "-data.msh", label + ".ele",
                                                          label + ".inp", label + ".msh", label + ".node",
                                                          label + ".poly", label + ".svg", label + ".vtu",
                                                          label + ".xdmf", label + "_facets.xdmf"}),
               boost::test_tools::per_element());
    check_vtu(mesh, dir.file(label + ".vtu"));
    check_msh(mesh, dir.file(label + ".msh"), false);
    check_msh(mesh, dir.file(label + "-data.msh"), true);
    check_inp(mesh, dir.file(label + ".inp"));
    check_triangle(mesh, dir.file(label));
    check_svg(mesh, dir.file(label + ".svg"), false);
    check_svg(mesh, dir.file(label + "-angle.svg"), true);

    // Independent XML parser, when python3 is around (it usually is).  The
    // real clients (meshio, gmsh, dolfinx) read these formats in
    // tests/python/test_solver_formats.py.
    std::string why;
    for (const std::string& name : {label + ".xdmf", label + "_facets.xdmf"}) BOOST_TEST(xml_balanced(slurp(dir.file(name)), why), why);
    if (have_python3()) {
        const std::string parse = "import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])";
        for (const std::string& name : {label + ".vtu", label + ".svg", label + "-angle.svg", label + ".xdmf", label + "_facets.xdmf"})
            BOOST_TEST(python_ok(parse, dir.file(name)), name);
    }
}

}  // namespace

// ---- round trips ---------------------------------------------------------------

BOOST_AUTO_TEST_CASE(square_round_trip) { round_trip(square_mesh(), "square"); }

BOOST_AUTO_TEST_CASE(grid_with_regions_and_cell_data_round_trip) { round_trip(grid_mesh(), "grid"); }

BOOST_AUTO_TEST_CASE(two_regions_with_interfaces_round_trip) { round_trip(two_region_mesh(), "two"); }

BOOST_AUTO_TEST_CASE(msh_22_carries_the_same_groups) {
    const Mesh m = two_region_mesh();
    TempDir dir;
    WriteOptions o;
    o.msh.version = 22;
    o.ascii = true;
    write_mesh(m, dir.file("old.msh"), o);
    std::istringstream in(slurp(dir.file("old.msh")));
    std::string line;
    std::getline(in, line);
    BOOST_TEST(line == "$MeshFormat");
    std::getline(in, line);
    BOOST_TEST(line == "2.2 0 8");
    const std::string s = slurp(dir.file("old.msh"));
    for (const std::string name : {"1 1 \"boundary\"", "1 2 \"domain_border\"", "1 3 \"interface_3_8\"",
                                   "2 3 \"left material\"", "2 8 \"domain_8\""})
        BOOST_TEST(s.find(name) != std::string::npos, name);
    // Element lines: "tag type 2 physical entity nodes…", triangles first.
    const std::size_t p = s.find("$Elements\n") + 10;
    std::istringstream el(s.substr(p));
    std::size_t n;
    el >> n;
    BOOST_REQUIRE_EQUAL(n, m.triangles.size() + m.boundary.size() + m.interfaces.size());
    for (std::size_t k = 0; k < n; ++k) {
        long tag, type, ntags, phys, entity;
        el >> tag >> type >> ntags >> phys >> entity;
        BOOST_TEST(tag == static_cast<long>(k + 1));
        BOOST_TEST(ntags == 2);
        BOOST_TEST(phys == entity);
        std::vector<long> nodes(type == 2 ? 3 : 2);
        for (auto& v : nodes) el >> v;
        if (k < m.triangles.size()) {
            BOOST_TEST(type == 2);
            BOOST_TEST(phys == m.region[k]);
            for (std::size_t c = 0; c < 3; ++c) BOOST_TEST(nodes[c] == m.triangles[k][c] + 1);
        } else if (k < m.triangles.size() + m.boundary.size()) {
            BOOST_TEST(type == 1);
            BOOST_TEST(phys == m.boundary_tag[k - m.triangles.size()]);
        } else {
            BOOST_TEST(type == 1);
            BOOST_TEST(phys == 3);
        }
    }
    BOOST_REQUIRE(el);
    o.msh.version = 30;
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.msh"), o), OutputError);
}

// Issue 27 item 5: with --background keep, .msh renumbered every region
// (background 1, label_5 2, …) while the other formats kept the labels.
BOOST_AUTO_TEST_CASE(msh_tags_are_the_labels_with_the_background_kept) {
    Mesh m = grid_mesh(3, 2);
    for (std::size_t k = 0; k < m.region.size(); ++k) m.region[k] = k % 3 == 0 ? 0 : k % 3 == 1 ? 5 : 7;
    m.region_names = {{0, "background"}, {5, "label_5"}, {7, "label_7"}};
    TempDir dir;
    for (const bool binary : {false, true}) {
        MshOptions o;
        o.binary = binary;
        write_msh(m, dir.file("keep.msh"), o);
        const std::string s = slurp(dir.file("keep.msh"));
        // $PhysicalNames is text in both encodings.
        for (const std::string name : {"2 5 \"label_5\"", "2 7 \"label_7\"", "2 8 \"background\""})
            BOOST_TEST(s.find(name) != std::string::npos, name << (binary ? " (binary)" : " (ASCII)"));
    }
}

BOOST_AUTO_TEST_CASE(xdmf_with_hdf5_writes_four_files_together) {
    const Mesh m = two_region_mesh();
    TempDir dir;
#ifdef WARPMESH_HAVE_HDF5
    write_mesh(m, dir.file("x.xdmf"));
    BOOST_TEST(dir.entries() == (std::vector<std::string>{"x.h5", "x.xdmf", "x_facets.h5", "x_facets.xdmf"}),
               boost::test_tools::per_element());
    const std::string xml = slurp(dir.file("x_facets.xdmf"));
    BOOST_TEST(xml.find(">x_facets.h5:/facets/topology<") != std::string::npos);
    BOOST_TEST(xml.find(">x.h5:/mesh/geometry<") != std::string::npos);
    // A failure on the way (here: the .h5 name is taken by a directory)
    // leaves none of the four files.
    TempDir blocked;
    fs::create_directory(blocked.file("y.h5"));
    BOOST_CHECK_THROW(write_mesh(m, blocked.file("y.xdmf")), OutputError);
    BOOST_TEST(blocked.entries() == std::vector<std::string>{"y.h5"}, boost::test_tools::per_element());
    // A staged name (the CLI's) refers to the final .h5 names.
    WriteOptions o;
    o.xdmf.final_path = dir.file("final.xdmf");
    write_mesh(m, dir.file(".staged.xdmf"), o);
    BOOST_TEST(slurp(dir.file(".staged.xdmf")).find(">final.h5:/mesh/topology<") != std::string::npos);
    BOOST_TEST(output_files(dir.file("z.xdmf")).size() == 4u);
#else
    BOOST_CHECK_THROW(write_mesh(m, dir.file("x.xdmf")), OutputError);
    BOOST_TEST(dir.entries().empty());
#endif
    WriteOptions text;
    text.ascii = true;
    BOOST_TEST(output_files(dir.file("z.xdmf"), text).size() == 2u);
}

BOOST_AUTO_TEST_CASE(negative_region_tags_get_positive_physicals) {
    Mesh m = grid_mesh(2, 2);
    for (auto& r : m.region) r = r == 3 ? -5 : 0;
    TempDir dir;
    MshOptions text;
    text.binary = false;
    write_msh(m, dir.file("neg.msh"), text);
    const Msh msh = read_msh(dir.file("neg.msh"));
    std::map<std::int32_t, std::string> names;
    for (const auto& [key, name] : msh.physical_names) {
        BOOST_TEST(key.second >= 1);
        if (key.first == 2) names[key.second] = name;
    }
    // Non-positive tags after the largest region tag (0 here): -5 → 1, 0 → 2.
    BOOST_TEST((names == std::map<std::int32_t, std::string>{{1, "domain_-5"}, {2, "domain_0"}}));
    // Abaqus names: letters, digits and '_' only.
    write_inp(m, dir.file("neg.inp"));
    const std::string inp = slurp(dir.file("neg.inp"));
    BOOST_TEST(inp.find("*ELSET, ELSET=domain__5\n") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(svg_coloured_by_cell_data) {
    const Mesh m = grid_mesh();
    TempDir dir;
    SvgOptions o;
    o.color_by_cell_data = "certified_min_angle";
    write_svg(m, dir.file("c.svg"), o);
    check_svg(m, dir.file("c.svg"), true);
    const std::string s = slurp(dir.file("c.svg"));
    BOOST_TEST(s.find(">certified_min_angle</text>") != std::string::npos);
    // Distinct values give distinct fills: the first and last triangles differ.
    BOOST_TEST(count(s, "fill=\"#d73027\"") >= 1u);  // the minimum is the low end (red)
    BOOST_TEST(count(s, "fill=\"#1a9850\"") >= 1u);  // the maximum the high end (green)

    o.color_by_cell_data = "no such array";
    BOOST_CHECK_THROW(write_svg(m, dir.file("bad.svg"), o), OutputError);
    BOOST_TEST(dir.entries() == std::vector<std::string>{"c.svg"}, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(empty_mesh_writes_valid_files) {
    const Mesh m;
    TempDir dir;
    WriteOptions text;
    text.ascii = true;
    for (const std::string name : {"e.vtu", "e.msh", "e.xdmf", "e.inp", "e.node", "e.svg"})
        BOOST_CHECK_NO_THROW(write_mesh(m, dir.file(name), text));
    for (const std::string name : {"b.vtu", "b.msh", "b.xdmf"}) BOOST_CHECK_NO_THROW(write_mesh(m, dir.file(name)));
    const Msh msh = read_msh(dir.file("e.msh"));
    BOOST_TEST(msh.elements.empty());
    std::string why;
    BOOST_TEST(xml_balanced(slurp(dir.file("e.vtu")), why), why);
    BOOST_TEST(xml_balanced(slurp(dir.file("e.svg")), why), why);
}

// ---- errors and atomicity ------------------------------------------------------

BOOST_AUTO_TEST_CASE(unknown_extension_is_an_error) {
    TempDir dir;
    for (const std::string name : {"mesh.obj", "mesh", "mesh.vtk", "mesh.json"}) {
        BOOST_CHECK_THROW(write_mesh(square_mesh(), dir.file(name)), OutputError);
        try {
            write_mesh(square_mesh(), dir.file(name));
        } catch (const OutputError& e) {
            BOOST_TEST(std::string(e.what()).find(dir.file(name)) != std::string::npos, e.what());
        }
    }
    BOOST_TEST(dir.entries().empty());
    // Extensions are case-insensitive.
    BOOST_CHECK_NO_THROW(write_mesh(square_mesh(), dir.file("UPPER.VTU")));
    BOOST_TEST(dir.entries() == std::vector<std::string>{"UPPER.VTU"}, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(missing_directory_is_an_error) {
    TempDir dir;
    const std::string path = dir.file("no/such/dir/mesh.vtu");
    try {
        write_mesh(square_mesh(), path);
        BOOST_FAIL("expected OutputError");
    } catch (const OutputError& e) {
        BOOST_TEST(std::string(e.what()).find(path) != std::string::npos, e.what());
    }
    BOOST_CHECK_THROW(write_triangle(square_mesh(), dir.file("no/such/x.node")), OutputError);
    BOOST_CHECK_THROW(write_quality_json(dir.file("no/r.json"), compute_quality(square_mesh())), OutputError);
    BOOST_TEST(dir.entries().empty());
}

BOOST_AUTO_TEST_CASE(unwritable_directory_is_an_error) {
    TempDir dir;
    // A "directory" that is a regular file fails even for root.
    write_file_atomically(dir.file("plain"), [](std::ostream& os) { os << "x"; });
    for (const std::string name : {"m.vtu", "m.msh", "m.node", "m.svg"})
        BOOST_CHECK_THROW(write_mesh(square_mesh(), dir.file("plain/" + name)), OutputError);
    BOOST_TEST(dir.entries() == std::vector<std::string>{"plain"}, boost::test_tools::per_element());
    fs::remove(dir.file("plain"));

    if (::geteuid() == 0) {
        BOOST_TEST_MESSAGE("running as root: directory permissions are not enforced, skipping the chmod case");
        return;
    }
    fs::permissions(dir.path, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
    for (const std::string name : {"m.vtu", "m.msh", "m.node", "m.svg"})
        BOOST_CHECK_THROW(write_mesh(square_mesh(), dir.file(name)), OutputError);
    fs::permissions(dir.path, fs::perms::owner_all, fs::perm_options::replace);
    BOOST_TEST(dir.entries().empty());
}

BOOST_AUTO_TEST_CASE(failure_midway_leaves_nothing_and_keeps_the_old_file) {
    TempDir dir;
    const std::string path = dir.file("out.txt");
    // A body that throws after writing part of the file.
    BOOST_CHECK_THROW(write_file_atomically(path,
                                            [](std::ostream& os) {
                                                os << "partial content\n";
                                                throw std::runtime_error("simulated failure");
                                            }),
                      OutputError);
    BOOST_TEST(dir.entries().empty());

    // A stream error (as a full disk would cause) is detected after the body.
    try {
        write_file_atomically(path, [](std::ostream& os) {
            os << "partial";
            os.setstate(std::ios::badbit);
        });
        BOOST_FAIL("expected OutputError");
    } catch (const OutputError& e) {
        BOOST_TEST(std::string(e.what()).find(path) != std::string::npos, e.what());
    }
    BOOST_TEST(dir.entries().empty());

    // An existing file is replaced only on success.
    write_file_atomically(path, [](std::ostream& os) { os << "old\n"; });
    BOOST_CHECK_THROW(write_file_atomically(path, [](std::ostream& os) { os << "new"; throw std::runtime_error("x"); }),
                      OutputError);
    BOOST_TEST(slurp(path) == "old\n");
    write_file_atomically(path, [](std::ostream& os) { os << "new\n"; });
    BOOST_TEST(slurp(path) == "new\n");
    BOOST_TEST(dir.entries() == std::vector<std::string>{"out.txt"}, boost::test_tools::per_element());

    // New files get the usual permissions (0666 & ~umask), not mkstemp's 0600.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    struct stat st {};
    BOOST_REQUIRE(::stat(path.c_str(), &st) == 0);
    BOOST_TEST((st.st_mode & 0777) == (0666 & ~mask));
}

BOOST_AUTO_TEST_CASE(inconsistent_mesh_is_an_error) {
    Mesh m = square_mesh();
    m.region.pop_back();
    TempDir dir;
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.msh")), OutputError);
    m = square_mesh();
    m.triangles[1][2] = 17;
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.vtu")), OutputError);
    m = square_mesh();
    m.cell_data.push_back({"short", {1.0}});
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.svg")), OutputError);
    m = two_region_mesh();
    m.interface_regions.pop_back();
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.xdmf")), OutputError);
    m = two_region_mesh();
    std::swap(m.interfaces[0][0], m.interfaces[0][1]);  // region 3 no longer on the edge's left
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.inp")), OutputError);
    BOOST_TEST(dir.entries().empty());
}

// ---- tetrahedra (issue 30) -------------------------------------------------------
// The round trips through meshio, gmsh, dolfinx, VTK and CalculiX are in
// tests/python/test_tet_formats.py; here the dispatcher and the errors.

BOOST_AUTO_TEST_CASE(tet_mesh_refuses_2d_formats_by_name) {
    const TetMesh m = testing::cube_tet_mesh(2, 1, 1);
    TempDir dir;
    for (const std::string name : {"t.node", "t.ele", "t.svg", "t.png"}) {
        try {
            write_mesh(m, dir.file(name));
            BOOST_FAIL("expected OutputError for " + name);
        } catch (const OutputError& e) {
            BOOST_TEST(std::string(e.what()).find("2D format") != std::string::npos, e.what());
            BOOST_TEST(std::string(e.what()).find(".vtu, .msh, .xdmf, .inp or .mesh") != std::string::npos, e.what());
        }
        BOOST_CHECK_THROW(check_output_path_3d(dir.file(name)), OutputError);
    }
    BOOST_CHECK_THROW(write_mesh(m, dir.file("t.obj")), OutputError);
    BOOST_TEST(dir.entries().empty());
    for (const std::string name : {"t.vtu", "t.msh", "t.inp", "t.mesh", "T.MESH"}) BOOST_CHECK_NO_THROW(write_mesh(m, dir.file(name)));
}

BOOST_AUTO_TEST_CASE(inconsistent_tet_mesh_is_an_error_and_writes_nothing) {
    TempDir dir;
    TetMesh m = testing::cube_tet_mesh(2, 1, 1);
    m.region.pop_back();
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.msh")), OutputError);
    m = testing::cube_tet_mesh(2, 1, 1);
    m.tets[3][1] = 1000;
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.vtu")), OutputError);
    m = testing::cube_tet_mesh(2, 1, 1);
    m.boundary_tag.pop_back();
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.mesh")), OutputError);
    m = testing::cube_tet_mesh(2, 1, 1);
    m.interface_regions.pop_back();
    BOOST_CHECK_THROW(write_mesh(m, dir.file("bad.xdmf")), OutputError);
    // A boundary triangle turned inwards is no outward face of a tetrahedron:
    // the .inp surface cannot name it.
    m = testing::cube_tet_mesh(2, 1, 1);
    std::swap(m.boundary[0][1], m.boundary[0][2]);
    try {
        write_mesh(m, dir.file("bad.inp"));
        BOOST_FAIL("expected OutputError");
    } catch (const OutputError& e) {
        BOOST_TEST(std::string(e.what()).find("not an outward face of a tetrahedron") != std::string::npos, e.what());
    }
    BOOST_TEST(dir.entries().empty());
}

BOOST_AUTO_TEST_CASE(medit_file_of_a_triangle_mesh) {
    // 2D meshes go to .mesh too: Dimension 2, Triangles, Edges.
    TempDir dir;
    write_mesh(two_region_mesh(), dir.file("two.mesh"));
    const std::string text = slurp(dir.file("two.mesh"));
    BOOST_TEST(text.rfind("MeshVersionFormatted 2\nDimension 2\nVertices\n", 0) == 0);
    BOOST_TEST(text.find("\nTriangles\n24\n") != std::string::npos);
    BOOST_TEST(text.find("\nEdges\n") != std::string::npos);
    BOOST_TEST(text.substr(text.size() - 4) == "End\n");
}

// ---- quality report ------------------------------------------------------------

BOOST_AUTO_TEST_CASE(triangle_angles_and_radius_ratio) {
    const double h = std::sqrt(3.0) / 2;
    const auto eq = triangle_angles({0, 0}, {1, 0}, {0.5, h});
    BOOST_TEST(eq.min_deg == 60.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(eq.max_deg == 60.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(radius_ratio({0, 0}, {1, 0}, {0.5, h}) == 1.0, boost::test_tools::tolerance(1e-12));

    const auto right = triangle_angles({0, 0}, {1, 0}, {0, 1});
    BOOST_TEST(right.min_deg == 45.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(right.max_deg == 90.0, boost::test_tools::tolerance(1e-12));
    // 2 r/R for the right isoceles triangle with legs 1: r = (2 - √2)/2,
    // R = √2/2, so 2 r/R = 2 (√2 - 1).
    BOOST_TEST(radius_ratio({0, 0}, {1, 0}, {0, 1}) == 2 * (std::sqrt(2.0) - 1), boost::test_tools::tolerance(1e-12));
    // Clockwise gives the same.
    BOOST_TEST(triangle_angles({0, 0}, {0, 1}, {1, 0}).max_deg == 90.0, boost::test_tools::tolerance(1e-12));

    // A sliver: angles near 0 and 180 are accurate (atan2, not acos).
    const auto sliver = triangle_angles({0, 0}, {1, 0}, {0.5, 1e-9});
    const double tiny = std::atan(2e-9) * 180 / std::numbers::pi;
    BOOST_TEST(sliver.min_deg == tiny, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(sliver.max_deg == 180 - 2 * tiny, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(radius_ratio({0, 0}, {1, 0}, {2, 0}) == 0.0);
    BOOST_TEST(radius_ratio({0, 0}, {0, 0}, {0, 0}) == 0.0);

    // Random triangles against the law of cosines for all three angles.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        const Vec2 p[3] = {{u(rng), u(rng)}, {u(rng), u(rng)}, {u(rng), u(rng)}};
        double mn = 180, mx = 0;
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = p[k], b = p[(k + 1) % 3], c = p[(k + 2) % 3];
            const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
            const double cosang = (ux * vx + uy * vy) / std::hypot(ux, uy) / std::hypot(vx, vy);
            const double ang = std::acos(std::clamp(cosang, -1.0, 1.0)) * 180 / std::numbers::pi;
            mn = std::min(mn, ang), mx = std::max(mx, ang);
        }
        const auto got = triangle_angles(p[0], p[1], p[2]);
        BOOST_TEST(std::abs(got.min_deg - mn) < 1e-6);
        BOOST_TEST(std::abs(got.max_deg - mx) < 1e-6);
    }
}

BOOST_AUTO_TEST_CASE(quality_report_of_hand_computed_meshes) {
    // The square split in two: two right isoceles triangles.
    const QualityReport q = compute_quality(square_mesh(), {{"sample", 0.25}, {"write", 0.5}});
    BOOST_TEST(q.vertices == 4);
    BOOST_TEST(q.triangles == 2);
    BOOST_TEST(q.boundary_edges == 4);
    BOOST_TEST(q.min_angle_deg == 45.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.max_angle_deg == 90.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.mean_min_angle_deg == 45.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.max_angle_over_90 == 0);  // right angles (to rounding) are not obtuse
    BOOST_TEST(q.radius_ratio_min == 2 * (std::sqrt(2.0) - 1), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.radius_ratio_mean == 2 * (std::sqrt(2.0) - 1), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.area == 1.0, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(q.nonpositive_triangles == 0);
    BOOST_TEST(q.boundary_length == 4.0, boost::test_tools::tolerance(1e-15));
    BOOST_TEST((q.boundary_edges_by_tag == std::map<std::int32_t, std::int64_t>{{1, 2}, {2, 2}}));
    BOOST_TEST(q.boundary_length_by_tag.at(1) == 2.0, boost::test_tools::tolerance(1e-15));
    BOOST_TEST((q.triangles_by_region == std::map<std::int32_t, std::int64_t>{{1, 2}}));
    // 45° lands in bin [44, 46) = 22.
    for (int i = 0; i < QualityReport::histogram_bins; ++i)
        BOOST_TEST(q.min_angle_histogram[static_cast<std::size_t>(i)] == (i == 22 ? 2 : 0), "bin " << i);

    // Equilateral + right isoceles + a 30-60-90 triangle, disjoint.
    Mesh m;
    const double h = std::sqrt(3.0) / 2;
    m.vertices = {{0, 0}, {1, 0}, {0.5, h}, {2, 0}, {3, 0}, {2, 1}, {4, 0}, {4 + std::sqrt(3.0), 0}, {4, 1}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
    m.region = {1, 2, 2};
    const QualityReport r = compute_quality(m);
    BOOST_TEST(r.min_angle_deg == 30.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.max_angle_deg == 90.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.mean_min_angle_deg == 45.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.max_angle_min_deg == 60.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.max_angle_mean_deg == 80.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.radius_ratio_min == std::sqrt(3.0) - 1, boost::test_tools::tolerance(1e-12));  // 30-60-90: 2r/R = √3 - 1
    BOOST_TEST(r.area == std::sqrt(3.0) / 4 + 0.5 + std::sqrt(3.0) / 2, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(r.min_angle_histogram[15] == 1);  // 30° → [30, 32)
    BOOST_TEST(r.min_angle_histogram[22] == 1);  // 45° → [44, 46)
    BOOST_TEST(r.min_angle_histogram[29] == 1);  // 60° → last bin [58, 60]
    BOOST_TEST((r.triangles_by_region == std::map<std::int32_t, std::int64_t>{{1, 1}, {2, 2}}));

    // An obtuse (120°) and an inverted triangle.
    Mesh o;
    o.vertices = {{0, 0}, {2, 0}, {1, 1 / std::sqrt(3.0)}, {0, 1}};
    o.triangles = {{0, 1, 2}, {0, 3, 1}};
    o.region = {1, 1};
    const QualityReport s = compute_quality(o);
    BOOST_TEST(s.max_angle_deg == 120.0, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(s.max_angle_over_90 == 1);
    BOOST_TEST(s.nonpositive_triangles == 1);

    // Empty mesh: no angles.
    const QualityReport e = compute_quality(Mesh{});
    BOOST_TEST(std::isnan(e.min_angle_deg));
    BOOST_TEST(quality_json(e).find("\"min_angle_deg\": null") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(quality_text_and_json) {
    const QualityReport q = compute_quality(grid_mesh(), {{"sample", 0.125}, {"triangulate", 0.5}});
    const std::string text = quality_text(q);
    BOOST_TEST(text.find("30 triangles") != std::string::npos, text);
    BOOST_TEST(text.find("minimum-angle histogram") != std::string::npos, text);
    BOOST_TEST(text.find("total") != std::string::npos, text);
    BOOST_TEST_MESSAGE(text);

    const std::string json = quality_json(q);
    BOOST_TEST(json.find("\"triangles\": 30") != std::string::npos, json);
    BOOST_TEST(json.find("\"total_seconds\": 0.625") != std::string::npos, json);
    BOOST_TEST(json.find("\"triangles_by_region\": {\"3\": 18, \"8\": 12}") != std::string::npos, json);
    BOOST_TEST(json.substr(json.size() - 3) == "\n}\n", json);

    // The 2D report: the quality's fields first, then each stage's in order.
    Mesh2dReport r;
    r.quality = q;
    r.lattice.input = "max-min \"quoted\"";
    r.lattice.nx = 5, r.lattice.ny = 3;
    r.certified.requested = true;  // no certificates: null
    const std::string full = to_json(r);
    BOOST_TEST(full.find(json.substr(0, json.size() - 3) + ",\n  \"input\": \"max-min \\\"quoted\\\"\"") == 0u, full);
    BOOST_TEST(full.find("\"lattice\": [5, 3]") != std::string::npos, full);
    BOOST_TEST(full.find("\"certified\": null") != std::string::npos, full);
    BOOST_TEST(full.find("\"repeat\"") == std::string::npos, full);  // only when > 1
    BOOST_TEST(to_text(r) == text);  // no certification, materials or optimisation lines

    TempDir dir;
    write_quality_json(dir.file("report.json"), q);
    BOOST_TEST(slurp(dir.file("report.json")) == json);
    if (have_python3()) {
        BOOST_TEST(python_ok("import sys, json; d = json.load(open(sys.argv[1])); "
                             "assert d[\"triangles\"] == 30 and len(d[\"min_angle_histogram\"][\"counts\"]) == 30",
                             dir.file("report.json")));
    }
}
