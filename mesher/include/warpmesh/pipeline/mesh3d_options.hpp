// mesh3d_options.hpp — the options of the 3D mesher by name (options.hpp):
// the command line's `warpmesh mesh3d` options and Python's keywords of
// mesh3d, lattice3d and mesh3d_block are this table's entries, their help
// its help.
#pragma once

#include "warpmesh/pipeline/mesh3d.hpp"  // Mesh3dOptions
#include "warpmesh/pipeline/options.hpp"

namespace warpmesh {

// Throws OptionError naming the option if a table option is out of range
// (spacing positive and finite).  The pipeline's validate(input, options)
// calls it, then checks what depends on the input.
void validate(const Mesh3dOptions& options, const GivenOptions& given = {});
// Throws OptionError unless max_size >= 2 · spacing (a volume's default
// spacing is known only once it is read: the pipeline checks it then).
void check_max_size(double max_size, double spacing);

// spacing, face_rule, verify, band, graded, max_size, grading, background, max_memory (threads, alphas, quality: set by
// the clients and by tests, not options).
const OptionTable<Mesh3dOptions>& mesh3d_option_table();

}  // namespace warpmesh
