// mesh3d_options.hpp — the options of the 3D mesher by name (options.hpp):
// the command line's `warpmesh mesh3d` options and Python's keywords of
// mesh3d, lattice3d and mesh3d_block are this table's entries, their help
// its help.
#pragma once

#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/pipeline/options.hpp"

namespace warpmesh {

// Throws OptionError naming the option if an option is out of range (spacing
// positive and finite).
void validate(const Mesh3dOptions& options, const GivenOptions& given = {});

// spacing, face_rule, verify, max_memory (threads, alphas, quality: set by
// the clients and by tests, not options).
const OptionTable<Mesh3dOptions>& mesh3d_option_table();

}  // namespace warpmesh
