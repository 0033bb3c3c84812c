// module.cpp — warpmesh._core, the C++ side of the Python module `warpmesh`
// (python/warpmesh/__init__.py holds the Python-facing API and its docs).
//
// Arrays: the mesh's arrays are returned as numpy views of the C++ buffers,
// kept alive by the result object (no copy); images come in as 2D uint16
// arrays (one copy into warpmesh::Image, which the level set turns into its
// own double field anyway) and go out of read_image as numpy arrays that own
// the decoded pixels (no copy).  The GIL is released while meshing.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/warpmesh.hpp"

namespace py = pybind11;
using namespace warpmesh;

namespace {

// A numpy view of `count` rows of `cols` T's at `data`, owned by `base`.
template <class T>
py::array view(const void* data, std::size_t count, std::size_t cols, py::handle base) {
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)}, strides{static_cast<py::ssize_t>(cols * sizeof(T))};
    if (cols > 1) shape.push_back(static_cast<py::ssize_t>(cols)), strides.push_back(sizeof(T));
    py::array a(py::dtype::of<T>(), shape, strides, count ? data : nullptr, base);
    // Read-only: the arrays describe one mesh; a caller who edits wants a copy.
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
}

// Result.<name>: a view of the array get(result), `cols` T's a row.
template <class T, class Result, class Get>
void def_view(py::class_<Result>& cls, const char* name, std::size_t cols, Get get) {
    cls.def_property_readonly(name, [cols, get](py::object self) {
        const auto& a = get(self.cast<const Result&>());
        return view<T>(a.data(), a.size(), cols, self);
    });
}

// Result.write(path, ascii, compress, xdmf_inline): the mesh through the
// writers, starting from base(result)'s options; the GIL released.
template <class Result, class Base>
void def_write(py::class_<Result>& cls, Base base) {
    cls.def(
        "write",
        [base](const Result& r, const std::string& path, bool ascii, bool compress, bool xdmf_inline) {
            WriteOptions wo = base(r);
            wo.ascii = ascii;
            if (compress) wo.vtu.encoding = VtuOptions::Encoding::zlib;
            wo.xdmf.hdf5 = !xdmf_inline;
            py::gil_scoped_release release;
            write_mesh(r.mesh, path, wo);
        },
        py::arg("path"), py::arg("ascii") = false, py::arg("compress") = false, py::arg("xdmf_inline") = false);
}

// The cell data arrays of a mesh as {name: view}.
template <class Result>
py::dict cell_data_views(py::object self, const Result& r) {
    py::dict d;
    for (const auto& [name, values] : r.mesh.cell_data) d[py::str(name)] = view<double>(values.data(), values.size(), 1, self);
    return d;
}

// What mesh3d returns to Python: the pipeline's result (mesh, report, warnings).
using Mesh3dResult = warpmesh::Mesh3dResult;

// A volume from a numpy array (z, y, x) and its geometry: voxel_size (mm;
// none: voxel units) and origin; the input of the 3D pipeline.
struct Volume3 {
    Volume volume;
};

// A volume's geometry and what its reader says of it, as a dict (the
// Python Volume's attributes): spacing, origin, axes (axes[a] the unit
// direction of index axis a: volume.hpp), physical, integer_valued, maxval,
// format, space, source, warnings.
py::dict volume_geometry(const Volume& v) {
    py::dict d;
    d["spacing"] = v.spacing, d["origin"] = v.origin, d["axes"] = v.axes;
    d["physical"] = v.physical, d["integer_valued"] = v.integer_valued, d["maxval"] = v.maxval;
    d["format"] = v.format, d["space"] = v.space, d["source"] = v.source, d["warnings"] = v.warnings;
    return d;
}

// The geometry of a dict of volume_geometry's onto a volume (its values
// set), refusing axes that are not a signed permutation (the readers').
void set_volume_geometry(Volume& v, const py::dict& d) {
    try {
        v.spacing = d["spacing"].cast<Vec3>(), v.origin = d["origin"].cast<Vec3>();
        v.axes = d["axes"].cast<std::array<Vec3, 3>>();
        v.physical = d["physical"].cast<bool>(), v.integer_valued = d["integer_valued"].cast<bool>();
        v.maxval = d["maxval"].cast<int>();
        v.format = d["format"].cast<std::string>(), v.space = d["space"].cast<std::string>();
        v.source = d["source"].cast<std::string>(), v.warnings = d["warnings"].cast<std::vector<std::string>>();
    } catch (const py::error_already_set& e) {
        throw InputError(std::string("a volume's geometry is incomplete: ") + e.what());
    } catch (const py::cast_error& e) {
        throw InputError(std::string("a volume's geometry has a value of the wrong type: ") + e.what());
    }
    for (const double s : v.spacing)
        if (!(s > 0) || !std::isfinite(s)) throw InputError("a volume's spacing must be positive and finite");
    std::array<bool, 3> used{};
    for (Vec3& a : v.axes) {
        const std::optional<Vec3> e = axis_aligned(a);
        if (!e) throw InputError("a volume's axes must be axis-aligned (each +-e_x, +-e_y or +-e_z), as the readers accept");
        for (std::size_t k = 0; k < 3; ++k)
            if ((*e)[k] != 0) {
                if (used[k]) throw InputError("a volume's axes must be a permutation of the coordinate axes");
                used[k] = true;
            }
        a = *e;
    }
}

// The pipeline's input: a shape string, a Volume3, a VolumeFile (a path) or
// MaterialShapes3 ("T=S;T=S").
Mesh3dInput mesh3d_input(const py::object& input) {
    if (py::isinstance<py::str>(input)) return Shape3{input.cast<std::string>()};
    if (py::isinstance<MaterialShapes3>(input)) return input.cast<MaterialShapes3>();
    if (py::isinstance<VolumeFile>(input)) return input.cast<VolumeFile>();
    return std::cref(input.cast<const Volume3&>().volume);
}

// Every option's doc (both tables), for spelling messages as keywords.
std::vector<const OptionDoc*> all_docs() {
    std::vector<const OptionDoc*> d = mesh2d_option_table().docs();
    for (const OptionDoc* x : mesh3d_option_table().docs()) d.push_back(x);
    return d;
}

// A Python number as the text the tables read: ints as they are, floats as
// the shortest text that reads back (non-finite ones as "nan", "inf": the
// table refuses them, naming the keyword).
std::string keyword_number(const std::string& name, py::handle v, const std::string& part = "") {
    if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v) || !PyNumber_Check(v.ptr()))
        throw OptionError(name, "{" + name + "}" + part + " expects a number, got " + py::repr(v).cast<std::string>());
    if (PyIndex_Check(v.ptr())) return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
    return warpmesh::number_text(py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>());
}

// The texts of keyword `name`'s value for its table entry (several for a
// dict of pairs), or OptionError naming the keyword when its type is wrong.
std::vector<std::string> option_texts(const OptionDoc& d, py::handle v) {
    const std::string name(d.name);
    switch (d.kind) {
        case OptionKind::flag: return {PyObject_IsTrue(v.ptr()) ? "true" : "false"};
        case OptionKind::number:
        case OptionKind::integer: return {keyword_number(name, v)};
        case OptionKind::choice:
        case OptionKind::text:
            if (!py::isinstance<py::str>(v))
                throw OptionError(name, "{" + name + "} expects a string, got " + py::repr(v).cast<std::string>());
            return {v.cast<std::string>()};
        case OptionKind::pairs: {
            if (!py::isinstance<py::dict>(v))
                throw OptionError(name, "{" + name + "} must be a dict {label: size}, got " +
                                            std::string(py::str(v.get_type().attr("__name__"))));
            std::vector<std::string> texts;
            for (const auto& [k, x] : v.cast<py::dict>()) texts.push_back(keyword_number(name, k, " label") + "=" + keyword_number(name, x, " size"));
            return texts;
        }
    }
    return {};
}

// Options from Python keywords through a table (the library parses and
// validates them); `input` names the input in the report.
template <class Options>
Options options_from(const OptionTable<Options>& table, const py::dict& kw, Options o = {}) {
    GivenOptions given;
    for (const auto& [key, value] : kw) {
        const std::string name = py::str(key).cast<std::string>();
        if (name == "input") continue;
        const Option<Options>* entry = table.find(name);
        if (!entry) throw OptionError(name, "unknown option '" + name + "'");
        for (const std::string& text : option_texts(*entry, value)) table.set(o, given, name, text);
    }
    table.validate(o, given);
    return o;
}

MeshOptions mesh_options(const py::dict& kw) {
    MeshOptions o;
    if (kw.contains("input")) o.input = kw["input"].cast<std::string>();
    return options_from(mesh2d_option_table(), kw, o);
}

// The 3D pipeline's options from keywords (__init__.py converts them): the
// table's (spacing, face_rule, verify, max_memory in MB) set and checked by
// the table, as the command line's; the input's (labels, iso, inside,
// voxel_size) and threads, checked by the pipeline's validate.
Mesh3dOptions mesh3d_options(const py::dict& kw) {
    py::dict table_kw;
    for (const auto& [key, value] : kw)
        if (mesh3d_option_table().find(py::str(key).cast<std::string>())) table_kw[key] = value;
    Mesh3dOptions o = options_from(mesh3d_option_table(), table_kw);
    if (kw.contains("threads")) o.threads = kw["threads"].cast<int>();
    if (kw.contains("labels")) o.labels = kw["labels"].cast<std::string>();
    if (kw.contains("iso")) o.iso = kw["iso"].cast<double>();
    if (kw.contains("inside")) o.inside_above = kw["inside"].cast<std::string>() == "above";
    if (kw.contains("voxel_size")) o.voxel_size = kw["voxel_size"].cast<std::vector<double>>();
    if (kw.contains("materials")) o.materials = kw["materials"].cast<std::string>();
    return o;
}

// The table of "mesh2d" or "mesh3d" for __init__.py: per option its name,
// kind, metavar, choices, help group, help (spelled as keywords) and the
// command line's flag.
py::list option_table(const std::string& which) {
    const std::vector<const OptionDoc*> docs = which == "mesh2d" ? mesh2d_option_table().docs() : mesh3d_option_table().docs();
    constexpr const char* kinds[] = {"flag", "number", "integer", "choice", "pairs", "text"};
    py::list out;
    for (const OptionDoc* d : docs) {
        py::dict e;
        e["name"] = std::string(d->name);
        e["kind"] = kinds[static_cast<int>(d->kind)];
        e["metavar"] = std::string(d->metavar);
        std::vector<std::string> choices(d->choices.begin(), d->choices.end());
        e["choices"] = choices;
        e["group"] = std::string(d->group);
        e["help"] = spell_options(d->help, all_docs(), Spelling::python);
        e["flag"] = cli_flag(*d);
        e["off_flag"] = std::string(d->off_flag);
        out.append(e);
    }
    return out;
}

// f: a LevelSet, or a MaterialField (multi-material meshes).
template <class Field>
MeshResult run(const Field& f, const MeshOptions& o, std::optional<int> threads) {
    py::gil_scoped_release release;
#ifdef _OPENMP
    // The thread count of this call only (OpenMP's setting is per calling thread).
    if (threads) omp_set_num_threads(*threads);
#else
    (void)threads;
#endif
    return mesh(f, o);
}

using Pixels = py::array_t<std::uint16_t, py::array::c_style | py::array::forcecast>;
// Where the pixel centres lie (x0, y0, sx, sy): image_levelset.hpp's
// PixelGeometry; none: pixel units.
using Geometry = std::optional<std::array<double, 4>>;

PixelGeometry pixel_geometry(const Geometry& g) {
    return g ? PixelGeometry{(*g)[0], (*g)[1], (*g)[2], (*g)[3]} : PixelGeometry{};
}

// The samples of a 2D uint16 array as an Image (a copy: the level sets keep
// their own fields anyway).
Image to_image(const Pixels& pixels, int maxval, const std::string& source) {
    if (pixels.ndim() != 2) throw InputError("the image must be a 2D array (rows, columns)");
    Image img;
    img.height = static_cast<int>(pixels.shape(0));
    img.width = static_cast<int>(pixels.shape(1));
    img.maxval = maxval;
    img.source = source;
    img.pixels.resize(static_cast<std::size_t>(pixels.size()));
    if (pixels.size()) std::memcpy(img.pixels.data(), pixels.data(), img.pixels.size() * sizeof(std::uint16_t));
    return img;
}

// MeshResult: the mesh's arrays as numpy views, the report, write().
void bind_result(py::module_& m) {
    py::class_<MeshResult> result(m, "MeshResult");
    def_view<double>(result, "points", 2, [](const MeshResult& r) -> const auto& { return r.mesh.vertices; });
    def_view<std::int32_t>(result, "triangles", 3, [](const MeshResult& r) -> const auto& { return r.mesh.triangles; });
    def_view<std::int32_t>(result, "regions", 1, [](const MeshResult& r) -> const auto& { return r.mesh.region; });
    def_view<std::int32_t>(result, "boundary_edges", 2, [](const MeshResult& r) -> const auto& { return r.mesh.boundary; });
    def_view<std::int32_t>(result, "boundary_tags", 1, [](const MeshResult& r) -> const auto& { return r.mesh.boundary_tag; });
    def_view<std::int32_t>(result, "interfaces", 2, [](const MeshResult& r) -> const auto& { return r.mesh.interfaces; });
    def_view<std::int32_t>(result, "interface_regions", 2,
                           [](const MeshResult& r) -> const auto& { return r.mesh.interface_regions; });
    result
        .def_property_readonly("cell_data", [](py::object self) { return cell_data_views(self, self.cast<const MeshResult&>()); })
        .def_property_readonly("region_names", [](const MeshResult& r) { return r.mesh.region_names; })
        .def_property_readonly("warnings", [](const MeshResult& r) { return r.warnings; })
        .def_property_readonly("spacing", [](const MeshResult& r) { return r.spacing; })
        .def_property_readonly("refinements", [](const MeshResult& r) { return r.refinements; })
        .def("to_json", [](const MeshResult& r) { return to_json(r); })
        .def("to_text", [](const MeshResult& r) { return to_text(r); });
    def_write(result, [](const MeshResult& r) { return write_options(r); });
}

// mesh_image, mesh_shape, mesh_materials: the warpmesh.mesh*() of
// python/warpmesh/__init__.py, which checks and converts their arguments.
void bind_meshing(py::module_& m) {
    m.def(
        "mesh_image",
        [](const Pixels& pixels, int maxval, std::optional<double> iso, bool inside_above, std::optional<std::vector<int>> labels, bool nonzero,
           const std::string& source, const Geometry& geometry, std::optional<int> threads, const py::dict& kw) {
            const MemoryCall call;  // max_memory counts what this call needs, not the caller's arrays
            const MeshOptions o = mesh_options(kw);
            const Image img = to_image(pixels, maxval, source);
            ImageLevelSetOptions io;
            io.geometry = pixel_geometry(geometry);
            if (labels || nonzero) {
                io.mode = ImageMode::label;
                io.label_nonzero = nonzero;
                if (labels) io.labels = *labels;
            } else {
                io.iso = iso;
                io.inside_above = inside_above;
            }
            const std::unique_ptr<LevelSet> f = image_levelset(img, io);
            return run(*f, o, threads);
        },
        py::arg("pixels"), py::arg("maxval"), py::arg("iso"), py::arg("inside_above"), py::arg("labels"),
        py::arg("nonzero"), py::arg("source"), py::arg("geometry"), py::arg("threads"), py::arg("options"));

    m.def(
        "mesh_shape",
        [](const std::string& spec, std::optional<int> threads, const py::dict& kw) {
            const MemoryCall call;
            const MeshOptions o = mesh_options(kw);
            const std::unique_ptr<LevelSet> f = parse_shape(spec);
            return run(*f, o, threads);
        },
        py::arg("spec"), py::arg("threads"), py::arg("options"));

    // Every label (spec "all") or the listed ones ("3,41,42"; the other pixels
    // are the background, tag 0) in one conforming mesh (materials.hpp).
    m.def(
        "mesh_materials",
        [](const Pixels& pixels, int maxval, const std::string& spec, const std::string& source,
           const Geometry& geometry, std::optional<int> threads, const py::dict& kw) {
            const MemoryCall call;
            const Image img = to_image(pixels, maxval, source);
            const MeshOptions o = mesh_options(kw);
            const std::unique_ptr<MaterialField> field = make_label_materials(img, spec, pixel_geometry(geometry), o.max_memory);
            return run(*field, o, threads);
        },
        py::arg("pixels"), py::arg("maxval"), py::arg("spec"), py::arg("source"),
        py::arg("geometry"), py::arg("threads"), py::arg("options"));

    m.def(
        "mesh_shapes",
        [](const std::string& spec, std::optional<int> threads, const py::dict& kw) {
            const MemoryCall call;
            const MeshOptions o = mesh_options(kw);
            const std::unique_ptr<MaterialField> field = parse_material_shapes(spec);
            return run(*field, o, threads);
        },
        py::arg("spec"), py::arg("threads"), py::arg("options"));
}

// A TetBlock as a dict of numpy arrays (picklable: dask ships blocks between
// processes) and back.
py::dict block_to_dict(TetBlock&& b) {
    auto owned = [](auto&& vec, std::size_t cols) {
        using T = typename std::decay_t<decltype(vec)>::value_type;
        auto* heap = new std::decay_t<decltype(vec)>(std::move(vec));
        py::capsule owner(heap, [](void* p) { delete static_cast<std::decay_t<decltype(vec)>*>(p); });
        const auto rows = heap->size();
        if constexpr (std::is_same_v<T, Point3>)
            return py::array_t<double>({rows, cols}, heap->empty() ? nullptr : &heap->front().x, owner);
        else if constexpr (requires { std::tuple_size<T>::value; })
            return py::array_t<typename T::value_type>({rows, cols}, heap->empty() ? nullptr : heap->front().data(), owner);
        else return py::array_t<T>({rows}, heap->data(), owner);
    };
    py::dict d;
    d["vertex_key"] = owned(std::move(b.vertex_key), 1);
    d["vertices"] = owned(std::move(b.vertices), 3);
    d["on_level_set"] = owned(std::move(b.on_level_set), 1);
    d["tets"] = owned(std::move(b.tets), 4);
    d["tet_key"] = owned(std::move(b.tet_key), 1);
    d["lattice_edge"] = owned(std::move(b.lattice_edge), 1);
    // Several materials: the regions and their names (empty for one region).
    d["region"] = owned(std::move(b.region), 1);
    py::list names;
    for (const auto& [tag, name] : b.region_names) names.append(py::make_tuple(tag, name));
    d["region_names"] = names;
    // What the block is a part of, and what the merge's report needs.
    d["lattice"] = py::dict(py::arg("spacing") = b.lattice.spacing,
                            py::arg("origin") = std::array<double, 3>{b.lattice.origin.x, b.lattice.origin.y, b.lattice.origin.z},
                            py::arg("cubes") = b.lattice.cubes);
    d["lo"] = b.range.lo, d["hi"] = b.range.hi;
    d["face_rule"] = std::string(face_rule_name(b.face_rule));
    d["alphas"] = std::array<std::int64_t, 4>{b.alphas.long_num, b.alphas.long_den, b.alphas.short_num, b.alphas.short_den};
    d["counts"] = std::array<std::int64_t, 6>{b.warped, b.all_zero_left_out, b.all_zero_filled, b.all_zero_voids,
                                              b.junction_background_tets, b.junction_tets};
    d["open_faces"] = owned(std::move(b.open_faces), 3);
    const BlockFacts& f = b.facts;
    py::list materials;
    for (const BlockFacts::Material& m : f.materials) materials.append(py::make_tuple(m.tag, m.name, m.voxels, m.reference_volume));
    d["facts"] = py::dict(py::arg("source") = f.source, py::arg("quality") = f.quality, py::arg("reference_volume") = f.reference_volume,
                          py::arg("feature_size") = f.feature_size, py::arg("resolution") = f.resolution,
                          py::arg("open_face_f") = owned(std::vector<std::array<double, 2>>(f.open_face_f), 2),
                          py::arg("materials") = materials, py::arg("warnings") = f.warnings, py::arg("part") = f.part,
                          py::arg("voxel_volume") = f.voxel_volume);
    return d;
}

// The scalar a row of T is made of (Point3: double; an array: its elements').
template <class T>
struct ScalarOf {
    using type = T;
};
template <>
struct ScalarOf<Point3> {
    using type = double;
};
template <class U, std::size_t N>
struct ScalarOf<std::array<U, N>> {
    using type = U;
};
template <class T>
using Scalar = typename ScalarOf<T>::type;

// d[name], or InputError naming the missing entry.
py::object entry(const py::dict& d, const char* name) {
    if (!d.contains(name))
        throw InputError(std::string("a block without '") + name + "': give the dicts mesh3d_block returns, unchanged");
    return d[name];
}

template <class T>
std::vector<T> from_array(const py::dict& d, const char* name, std::size_t per) {
    const auto a = entry(d, name).cast<py::array_t<Scalar<T>, py::array::c_style | py::array::forcecast>>();
    if (static_cast<std::size_t>(a.size()) % per) throw InputError(std::string("block array '") + name + "' has a bad shape");
    std::vector<T> out(static_cast<std::size_t>(a.size()) / per);
    if (!out.empty()) std::memcpy(out.data(), a.data(), out.size() * sizeof(T));
    return out;
}

// A block from its dict (block_to_dict's); InputError for a missing entry
// or a value of the wrong type.
TetBlock block_from_dict(const py::dict& d) {
    TetBlock b;
    try {
        b.vertex_key = from_array<std::uint64_t>(d, "vertex_key", 1);
        b.vertices = from_array<Point3>(d, "vertices", 3);
        b.on_level_set = from_array<std::uint8_t>(d, "on_level_set", 1);
        b.tets = from_array<std::array<std::int32_t, 4>>(d, "tets", 4);
        b.tet_key = from_array<std::uint64_t>(d, "tet_key", 1);
        b.lattice_edge = from_array<std::uint8_t>(d, "lattice_edge", 1);
        b.region = from_array<std::int32_t>(d, "region", 1);
        for (const auto& item : entry(d, "region_names").cast<py::list>()) {
            const auto pair = item.cast<py::tuple>();
            b.region_names.emplace_back(pair[0].cast<std::int32_t>(), pair[1].cast<std::string>());
        }
        const py::dict lattice = entry(d, "lattice").cast<py::dict>();
        b.lattice.spacing = entry(lattice, "spacing").cast<double>();
        const auto origin = entry(lattice, "origin").cast<std::array<double, 3>>();
        b.lattice.origin = {origin[0], origin[1], origin[2]};
        b.lattice.cubes = entry(lattice, "cubes").cast<std::array<std::int64_t, 3>>();
        b.range = {entry(d, "lo").cast<std::array<std::int64_t, 3>>(), entry(d, "hi").cast<std::array<std::int64_t, 3>>()};
        const auto rule = parse_face_rule(entry(d, "face_rule").cast<std::string>());
        if (!rule) throw InputError("a block's face_rule is not parity or delaunay");
        b.face_rule = *rule;
        const auto a = entry(d, "alphas").cast<std::array<std::int64_t, 4>>();
        b.alphas = {a[0], a[1], a[2], a[3]};
        const auto c = entry(d, "counts").cast<std::array<std::int64_t, 6>>();
        b.warped = c[0], b.all_zero_left_out = c[1], b.all_zero_filled = c[2], b.all_zero_voids = c[3];
        b.junction_background_tets = c[4], b.junction_tets = c[5];
        b.open_faces = from_array<std::array<std::int32_t, 3>>(d, "open_faces", 3);
        const py::dict f = entry(d, "facts").cast<py::dict>();
        BlockFacts& x = b.facts;
        x.source = entry(f, "source").cast<std::string>();
        x.quality = entry(f, "quality").cast<bool>();
        x.reference_volume = entry(f, "reference_volume").cast<std::optional<double>>();
        x.feature_size = entry(f, "feature_size").cast<double>(), x.resolution = entry(f, "resolution").cast<double>();
        x.open_face_f = from_array<std::array<double, 2>>(f, "open_face_f", 2);
        for (const auto& item : entry(f, "materials").cast<py::list>()) {
            const auto m = item.cast<py::tuple>();
            x.materials.push_back({m[0].cast<std::int32_t>(), m[1].cast<std::string>(), m[2].cast<std::optional<std::int64_t>>(),
                                   m[3].cast<std::optional<double>>()});
        }
        x.warnings = entry(f, "warnings").cast<std::vector<std::string>>();
        x.part = entry(f, "part").cast<bool>(), x.voxel_volume = entry(f, "voxel_volume").cast<double>();
    } catch (const py::cast_error& e) {
        throw InputError(std::string("a block with an entry of the wrong type (give the dicts mesh3d_block returns): ") + e.what());
    }
    return b;
}

// One region's facts (levelset3.hpp: LabelRegionFacts) as a dict of plain
// values (picklable), and back; InputError for a missing entry or a value of
// the wrong type.
py::dict facts_to_dict(const LabelRegionFacts& f) {
    return py::dict(py::arg("labels") = f.labels, py::arg("of") = f.of, py::arg("whole") = f.whole, py::arg("owned_lo") = f.owned_lo,
                    py::arg("owned_hi") = f.owned_hi, py::arg("lo") = f.lo, py::arg("hi") = f.hi, py::arg("voxels") = f.voxels,
                    py::arg("lowest") = f.lowest, py::arg("deepest") = f.deepest,
                    py::arg("seen") = std::vector<int>(f.seen.begin(), f.seen.end()));
}
LabelRegionFacts facts_from_dict(const py::handle& h) {
    if (!py::isinstance<py::dict>(h))
        throw InputError("region facts must be the dicts region_part_facts and merge_region_facts return, got " +
                         py::repr(h).cast<std::string>());
    const py::dict d = h.cast<py::dict>();
    const auto need = [&](const char* name) {
        if (!d.contains(name))
            throw InputError(std::string("region facts without '") + name + "': give the dicts merge_region_facts returns, unchanged");
        return d[name];
    };
    LabelRegionFacts f;
    try {
        f.labels = need("labels").cast<std::string>(), f.of = need("of").cast<std::string>();
        f.whole = need("whole").cast<std::array<std::int64_t, 3>>();
        f.owned_lo = need("owned_lo").cast<std::array<std::int64_t, 3>>();
        f.owned_hi = need("owned_hi").cast<std::array<std::int64_t, 3>>();
        f.lo = need("lo").cast<std::array<std::int64_t, 3>>(), f.hi = need("hi").cast<std::array<std::int64_t, 3>>();
        f.voxels = need("voxels").cast<std::int64_t>();
        f.lowest = need("lowest").cast<double>(), f.deepest = need("deepest").cast<double>();
        for (const int x : need("seen").cast<std::vector<int>>()) f.seen.push_back(x != 0);
    } catch (const py::cast_error& e) {
        throw InputError(std::string("region facts with an entry of the wrong type (give the dicts merge_region_facts returns): ") +
                         e.what());
    }
    return f;
}
// None or the whole region's facts (mesh3d_block's region_facts=).
std::optional<LabelRegionFacts> optional_facts(const py::object& region) {
    if (region.is_none()) return std::nullopt;
    return facts_from_dict(region);
}

// The reduction before one region's blocks of parts (pipeline/mesh3d.hpp):
// warpmesh.region_part_voxels, region_part_facts, merge_region_facts.
void bind_region_facts(py::module_& m) {
    using Box = std::array<std::array<std::int64_t, 3>, 2>;
    m.def(
        "region_part_voxels",
        [](const py::object& input, const Box& owned, const py::dict& kw) {
            return region_part_voxels(mesh3d_input(input), mesh3d_options(kw), owned);
        },
        py::arg("input"), py::arg("owned"), py::arg("options"));
    m.def(
        "region_part_facts",
        [](const py::object& input, const Box& owned, const py::dict& kw) {
            const Mesh3dOptions o = mesh3d_options(kw);
            const Mesh3dInput in = mesh3d_input(input);
            LabelRegionFacts f;
            {
                py::gil_scoped_release release;
                f = region_part_facts(in, o, owned);
            }
            return facts_to_dict(f);
        },
        py::arg("input"), py::arg("owned"), py::arg("options"));
    m.def(
        "merge_region_facts",
        [](const py::list& parts) {
            std::vector<LabelRegionFacts> facts;
            for (const py::handle& p : parts) facts.push_back(facts_from_dict(p));
            return facts_to_dict(merge_region_facts(facts));
        },
        py::arg("parts"));
}

// The block API (pipeline/mesh3d.hpp, "Blocks"): the lattice of an input,
// one block of its cubes, the merge; warpmesh.lattice3d, mesh3d_block and
// merge_blocks in __init__.py.
void bind_blocks(py::module_& m) {
    bind_region_facts(m);
    m.def(
        "lattice3",
        [](const py::object& input, const py::dict& kw, const py::object& region) {
            const MemoryCall call;
            const Mesh3dOptions o = mesh3d_options(kw);
            const Mesh3dInput in = mesh3d_input(input);
            const std::optional<LabelRegionFacts> facts = optional_facts(region);
            py::gil_scoped_release release;
            return lattice3d(in, o, facts ? &*facts : nullptr).cubes;
        },
        py::arg("input"), py::arg("options"), py::arg("region") = py::none());
    m.def(
        "mesh3d_block",
        [](const py::object& input, std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> hi, const py::dict& kw,
           const py::object& region) {
            const MemoryCall call;
            const Mesh3dOptions o = mesh3d_options(kw);
            const Mesh3dInput in = mesh3d_input(input);
            const std::optional<LabelRegionFacts> facts = optional_facts(region);
            TetBlock b;
            {
                py::gil_scoped_release release;
                b = mesh3d_block(in, o, CubeRange{lo, hi}, facts ? &*facts : nullptr);
            }
            return block_to_dict(std::move(b));
        },
        py::arg("input"), py::arg("lo"), py::arg("hi"), py::arg("options"), py::arg("region") = py::none());
    m.def(
        "block_voxels",
        [](const py::object& input, std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> hi, std::int64_t halo,
           const py::dict& kw, const py::object& region) {
            const Mesh3dOptions o = mesh3d_options(kw);
            const Mesh3dInput in = mesh3d_input(input);
            const std::optional<LabelRegionFacts> facts = optional_facts(region);
            py::gil_scoped_release release;
            return block_voxels(in, o, CubeRange{lo, hi}, halo, facts ? &*facts : nullptr);
        },
        py::arg("input"), py::arg("lo"), py::arg("hi"), py::arg("halo"), py::arg("options"), py::arg("region") = py::none());
    // Partitioned output (pipeline/mesh3d.hpp): a block as a .vtu piece,
    // blocks as pieces and their .pvtu, a .pvtu of pieces written elsewhere.
    const auto vtu_options = [](bool compress) {
        VtuOptions o;
        if (compress) o.encoding = VtuOptions::Encoding::zlib;
        return o;
    };
    m.def(
        "write_block_vtu",
        [vtu_options](const py::dict& d, const std::string& path, bool compress) {
            const TetBlock b = block_from_dict(d);
            py::gil_scoped_release release;
            write_block_vtu(b, path, vtu_options(compress));
        },
        py::arg("block"), py::arg("path"), py::arg("compress"));
    m.def(
        "write_blocks_pvtu",
        [vtu_options](const std::string& path, const std::vector<py::dict>& dicts, bool compress) {
            std::vector<TetBlock> blocks;
            for (const py::dict& d : dicts) blocks.push_back(block_from_dict(d));
            py::gil_scoped_release release;
            return write_blocks_pvtu(path, blocks, vtu_options(compress));
        },
        py::arg("path"), py::arg("blocks"), py::arg("compress"));
    m.def(
        "write_pvtu", [](const std::string& path, const std::vector<std::string>& pieces) { write_pvtu(path, pieces); },
        py::arg("path"), py::arg("pieces"));
    m.def(
        "check_blocks",
        [](const std::vector<py::dict>& dicts) {
            std::vector<TetBlock> blocks;
            for (const py::dict& d : dicts) blocks.push_back(block_from_dict(d));
            check_blocks(blocks);
        },
        py::arg("blocks"));
    m.def(
        "merge_tet_blocks",
        [](const std::vector<py::dict>& dicts) {
            std::vector<TetBlock> blocks;
            for (const py::dict& d : dicts) blocks.push_back(block_from_dict(d));
            py::gil_scoped_release release;
            return merge_mesh3d_blocks(blocks);
        },
        py::arg("blocks"));
}

// The 3D pipeline (pipeline/mesh3d.hpp) on a shape string or a Volume3,
// and mesh3d_function (a Python callable f(x, y, z) on a box): the
// warpmesh.mesh3d() of python/warpmesh/__init__.py, which converts their
// arguments.
void bind_mesh3d(py::module_& m) {
    using Voxels = py::array_t<double, py::array::c_style | py::array::forcecast>;
    py::class_<Mesh3dResult> result(m, "Mesh3dResult");
    static_assert(sizeof(Point3) == 3 * sizeof(double));
    def_view<double>(result, "points", 3, [](const Mesh3dResult& r) -> const auto& { return r.mesh.vertices; });
    def_view<std::int32_t>(result, "tetrahedra", 4, [](const Mesh3dResult& r) -> const auto& { return r.mesh.tets; });
    def_view<std::int32_t>(result, "regions", 1, [](const Mesh3dResult& r) -> const auto& { return r.mesh.region; });
    def_view<std::int32_t>(result, "boundary_faces", 3, [](const Mesh3dResult& r) -> const auto& { return r.mesh.boundary; });
    def_view<std::int32_t>(result, "boundary_tags", 1, [](const Mesh3dResult& r) -> const auto& { return r.mesh.boundary_tag; });
    def_view<std::int32_t>(result, "interfaces", 3, [](const Mesh3dResult& r) -> const auto& { return r.mesh.interfaces; });
    def_view<std::int32_t>(result, "interface_regions", 2,
                           [](const Mesh3dResult& r) -> const auto& { return r.mesh.interface_regions; });
    result.def_property_readonly("cell_data", [](py::object self) { return cell_data_views(self, self.cast<const Mesh3dResult&>()); })
        .def_property_readonly("region_names", [](const Mesh3dResult& r) { return r.mesh.region_names; })
        .def_property_readonly("warnings", [](const Mesh3dResult& r) { return r.warnings; })
        .def("to_json", [](const Mesh3dResult& r) { return to_json(r.report); })
        .def("to_text", [](const Mesh3dResult& r) { return to_text(r.report); });
    def_write(result, [](const Mesh3dResult&) { return WriteOptions{}; });

    py::class_<Volume3>(m, "Volume3")
        .def(py::init([](const Voxels& a, bool integer_valued, std::optional<std::array<double, 3>> voxel_size,
                         std::array<double, 3> origin, std::optional<py::dict> geometry,
                         std::optional<std::array<std::array<std::int64_t, 3>, 2>> part) {
                 if (a.ndim() != 3) throw InputError("the volume must be a 3D array (z, y, x)");
                 Volume3 v;
                 v.volume.dims = {a.shape(2), a.shape(1), a.shape(0)};
                 v.volume.values.assign(a.data(), a.data() + a.size());
                 if (voxel_size) v.volume.spacing = *voxel_size;
                 v.volume.origin = origin, v.volume.physical = voxel_size.has_value();
                 v.volume.integer_valued = integer_valued;
                 v.volume.format = "numpy", v.volume.source = "the array";
                 if (geometry) set_volume_geometry(v.volume, *geometry);
                 // A part of a larger volume: (offset, whole dimensions), both (i, j, k).
                 if (part) v.volume.part_offset = (*part)[0], v.volume.whole_dims = (*part)[1];
                 return v;
             }),
             py::arg("volume"), py::arg("integer_valued"), py::arg("voxel_size"), py::arg("origin"),
             py::arg("geometry") = std::nullopt, py::arg("part") = std::nullopt);
    py::class_<VolumeFile>(m, "VolumeFile").def(py::init([](std::string path) { return VolumeFile{std::move(path)}; }), py::arg("path"));
    py::class_<MaterialShapes3>(m, "MaterialShapes3")
        .def(py::init([](std::string spec) { return MaterialShapes3{std::move(spec)}; }), py::arg("spec"));
    m.def(
        "mesh3d",
        [](const py::object& input, const py::dict& kw) {
            const MemoryCall call;
            const Mesh3dOptions o = mesh3d_options(kw);
            const Mesh3dInput in = mesh3d_input(input);
            py::gil_scoped_release release;
            return mesh3d(in, o);
        },
        py::arg("input"), py::arg("options"));
    bind_blocks(m);
    // A Python callable, evaluated with the GIL held: one thread (OpenMP
    // threads would only queue for the GIL).  An exception in it must not
    // cross the mesher's OpenMP regions: the first one's message is kept, the
    // point is taken as outside, and InputError is raised after meshing.
    m.def(
        "mesh3d_function",
        [](py::function f, std::array<double, 6> box, const py::dict& kw) {
            const MemoryCall call;
            // The function's first failure, in the user's words: its Python
            // exception's type and message (not pybind11's wrapping with a
            // traceback), or a value that is no finite number.
            auto error = std::make_shared<std::string>();
            FunctionLevelSet3 ls(
                [f, error](double x, double y, double z) {
                    py::gil_scoped_acquire gil;
                    if (!error->empty()) return 1.0;
                    try {
                        const double v = f(x, y, z).cast<double>();
                        if (std::isfinite(v)) return v;
                        *error = "gave f(" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                                 "), which is not a finite number";
                    } catch (py::error_already_set& e) {
                        *error = "raised " + py::str(e.type().attr("__name__")).cast<std::string>() + ": " +
                                 py::str(e.value()).cast<std::string>();
                    } catch (const std::exception& e) {
                        *error = std::string("failed: ") + e.what();
                    }
                    return 1.0;
                },
                Box3{box[0], box[1], box[2], box[3], box[4], box[5]}, "a Python function");
            Mesh3dOptions o = mesh3d_options(kw);
            o.threads = 1;
            std::optional<Mesh3dResult> r;
            std::string failure;
            try {
                py::gil_scoped_release release;
                r = mesh3d(std::cref(static_cast<const LevelSet3&>(ls)), o);
            } catch (const InputError& e) {
                failure = e.what();
            }
            if (!error->empty()) throw InputError("the level-set function " + *error);
            if (!r) throw InputError(failure);
            return std::move(*r);
        },
        py::arg("f"), py::arg("box"), py::arg("options"));
}

void bind_read_image(py::module_& m) {
    // (pixels, maxval, placement): pixels an array that owns the decoded
    // samples.  Any format the command line reads (read_volume: PGM, PNG,
    // NRRD, NIfTI, TIFF); a volume needs `slice` ("k=60", as --slice).  The
    // rows and columns are the slice as the command line meshes it: its first
    // in-plane index axis along the columns, its second upwards (row 0 at the
    // top, y = rows-1-r).  Samples must be integers in 0..65535 (label maps,
    // 8/16-bit images).  placement: where the pixels lie in `units` ("mm",
    // "pixels", or None: millimetres when the file gives a physical geometry,
    // as the command line's default), place_slice (volume.hpp): a dict with
    // "units", "geometry" (x0, y0, sx, sy) and the plane's "origin",
    // "x_axis", "y_axis", "normal"; None for a plain image in pixels.
    m.def(
        "read_image",
        [](const std::string& path, std::optional<std::string> slice, std::optional<std::string> units,
           std::uint64_t max_pixels, std::uint64_t max_memory) {
            if (units && *units != "mm" && *units != "pixels")
                throw InputError("units must be None, 'mm' or 'pixels', got '" + *units + "'");
            VolumeLimits limits;
            limits.max_voxels = max_pixels;
            limits.max_bytes = max_memory;
            const Volume v = read_volume(path, limits);
            if (!slice && v.dims[2] != 1)
                throw InputError(path + ": a volume of " + std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) +
                                 " x " + std::to_string(v.dims[2]) + " voxels: choose a slice, e.g. slice=\"k=0\"");
            const std::optional<SliceSpec> spec = slice ? std::optional(parse_slice(*slice)) : std::nullopt;
            const SlicePlacement at = place_slice(v, spec, units == "pixels" ? Units::pixels : Units::physical);
            if (units == "mm" && !at.physical)
                throw InputError(path + " (" + v.format + ") gives no physical pixel size: read it in pixels "
                                 "(units=None or \"pixels\") and scale with mesh(..., pixel_size=...)");
            py::object placement = py::none();
            if (at.placed) {
                const PixelGeometry& g = at.geometry;
                py::dict d;
                d["units"] = at.units;
                d["geometry"] = py::make_tuple(g.x0, g.y0, g.sx, g.sy);
                d["origin"] = at.plane.origin, d["x_axis"] = at.plane.x_axis, d["y_axis"] = at.plane.y_axis;
                d["normal"] = at.plane.normal;
                placement = d;
            }
            auto img = std::make_unique<Image>(slice_image(v, spec));
            const int maxval = img->maxval;
            const std::array<py::ssize_t, 2> shape{img->height, img->width};
            std::uint16_t* data = img->pixels.data();
            py::capsule owner(img.release(), [](void* p) { delete static_cast<Image*>(p); });
            return py::make_tuple(py::array_t<std::uint16_t>(shape, data, owner), maxval, placement);
        },
        py::arg("path"), py::arg("slice") = std::nullopt, py::arg("units") = std::nullopt,
        py::arg("max_pixels") = default_max_pixels, py::arg("max_memory") = default_max_memory);
    // (values, geometry): a volume as the command line reads it (read_volume:
    // NRRD, NIfTI, TIFF, PGM, PNG), values a float64 array (z, y, x) that owns
    // the decoded samples (converted from 16-bit labels where the reader kept
    // them so), geometry a dict of volume_geometry's.
    m.def(
        "read_volume",
        [](const std::string& path, std::uint64_t max_voxels, std::uint64_t max_memory) {
            auto v = std::make_unique<Volume>(read_volume(path, {max_voxels, max_memory}));
            const std::array<py::ssize_t, 3> shape{v->dims[2], v->dims[1], v->dims[0]};
            py::dict geometry = volume_geometry(*v);
            samples_to_values(*v);  // float64, whatever the reader kept
            double* data = v->values.data();
            py::capsule owner(v.release(), [](void* p) { delete static_cast<Volume*>(p); });
            return py::make_tuple(py::array_t<double>(shape, data, owner), geometry);
        },
        py::arg("path"), py::arg("max_voxels"), py::arg("max_memory"));
}

}  // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "warpmesh C++ core (use the `warpmesh` package)";
    const auto& input_error = py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
    // OptionError: an InputError whose message names the options as keywords.
    static py::exception<OptionError> option_error(m, "OptionError", input_error.ptr());
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const OptionError& e) {
            PyErr_SetString(option_error.ptr(), spell_options(e.message(), all_docs(), Spelling::python).c_str());
        }
    });
    py::register_exception<OutputError>(m, "OutputError", PyExc_OSError);
    bind_result(m);
    bind_meshing(m);
    bind_mesh3d(m);
    bind_read_image(m);
    m.def("option_table", &option_table, py::arg("which"));
    m.def("png_supported", &png_supported);
    m.def("certified_table_available", &certified_table_available);
}
