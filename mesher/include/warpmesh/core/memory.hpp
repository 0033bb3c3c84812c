// memory.hpp — the memory bound: admission checks made before each
// input-sized stage starts, so that an input over the limit is refused with
// a message instead of exhausting the machine.
//
// The bound.  What a call needs — its peak resident memory above what the
// process held when the call began — is at most (about) the limit L (the
// command line's --max-memory, Python's max_memory, default_max_memory =
// 2 GiB), because every stage that allocates in proportion to the input
// first checks
//
//     (resident memory now − the call's baseline) + (its bytes a unit) x (its units)  <=  L
//
// and throws OptionError naming max_memory otherwise.  The baseline is the
// resident memory when the outermost MemoryCall began: the command line
// opens one at its start (a run's whole memory counts, its input included),
// Python's functions and the pipelines' entry points one each, so memory the
// caller holds already (a Python caller's arrays, a C++ program's data) does
// not count against the call.  The stages and their
// costs (worst cases: an image of random noise, every square on the
// boundary; measured with /usr/bin/time -v, see docs):
//
//   reading a file       the file's bytes, inflated data and 8 bytes a voxel
//                        (volume_detail.hpp: checked_voxels; image_io.cpp)
//   a slice's field      field_bytes_per_pixel(kind) a pixel of the slice
//                        (load_slice, make_label_materials)
//   meshing              mesh_bytes_per_square(...) a lattice square, plus
//                        mesh_bytes_per_material() a material
//                        (mesh(); analytic shapes with --graded excepted:
//                        their memory follows the boundary's length, which
//                        the shape string does not bound in advance)
//   optimising (2D)      optimize_bytes_per_square(...) a lattice square in
//                        the admission of a uniform mesh, then, with the
//                        mesh made, optimize_bytes_per_triangle(...) a
//                        triangle before the pass starts (graded meshes have
//                        far fewer triangles than squares)
#pragma once

#include <cstdint>
#include <string>

namespace warpmesh {

// The process's resident memory now, in bytes (Linux: /proc/self/statm;
// 0 where it cannot be read).
std::uint64_t resident_bytes();

// A call the memory bound applies to, for as long as the object lives: the
// first one (of any thread) records the baseline, resident_bytes() now; the
// others, nested or concurrent, keep it (so concurrent calls count each
// other's memory: the bound stays conservative); when the last ends, the
// baseline is 0 again (the whole process counts).
class MemoryCall {
public:
    MemoryCall();
    ~MemoryCall();
    MemoryCall(const MemoryCall&) = delete;
    MemoryCall& operator=(const MemoryCall&) = delete;
};
// The baseline now (0 outside every MemoryCall).
std::uint64_t memory_baseline();

// What a slice's level set or material field costs a pixel while it is built
// and held.
enum class FieldKind { threshold, label, materials };
std::uint64_t field_bytes_per_pixel(FieldKind kind);

// What meshing costs a lattice square at most, with everything written
// (cell data, pictures): one region or several materials, uniform or graded.
std::uint64_t mesh_bytes_per_square(bool materials, bool graded);
// And a material (its report, names and tables), on top: at most 65 536.
std::uint64_t mesh_bytes_per_material();
// What the optimisation pass (--optimize) adds, above the mesh it works on:
// a triangle of the mesh (its stars, kinds, curves and trial buffers), and a
// lattice square of a uniform mesh (two triangles a square at most).
std::uint64_t optimize_bytes_per_triangle(bool materials);
std::uint64_t optimize_bytes_per_square(bool materials);

// Throws OptionError (max_memory) "<what> needs about N MB (<how>) on top of
// the R MB this call holds already, N + R MB in all, more than the
// {max_memory} limit of L MB; raise {max_memory} ..., or <advice>" when
// R = resident_bytes() − memory_baseline() (at least 0) and R + need >
// max_memory.
void check_memory(std::uint64_t need, std::uint64_t max_memory, const std::string& what, const std::string& how,
                  const std::string& advice);

}  // namespace warpmesh
