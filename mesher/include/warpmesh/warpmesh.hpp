// warpmesh.hpp — the whole public API in one include.
//
// One folder per layer, low to high (ARCHITECTURE.md, "Layers"; the rules are
// scripts/check-layers.py's).  No library header includes this one.
//
//   core/mesh.hpp              the mesh: vertices, triangles, regions, boundary, interfaces
//   core/tet_mesh.hpp          the 3D mesh: vertices, tetrahedra, boundary faces
//   core/triangle_shape.hpp    one triangle's angles, radius ratio, area
//   core/errors.hpp            InputError, OutputError
//   core/memory.hpp            the memory budget (--max-memory) and its admission checks
//   io/image.hpp               read_image / decode_image: PGM, PNG (warpmesh::io)
//   io/volume.hpp              read_volume: NRRD, NIfTI, TIFF; where a slice lies (warpmesh::io)
//   io/writers.hpp             .vtu .msh .xdmf .inp .mesh .node/.ele .svg .png (warpmesh::io)
//   levelset/levelset.hpp      the region to mesh: f < 0 inside (implement it for your own f)
//   levelset/shapes.hpp        analytic shapes from strings: "circle:0,0,1", "diff(S;S)", ...
//   levelset/image_levelset.hpp  images → level sets: threshold or labels
//   mesh2d/materials.hpp       multi-material fields (label images, shapes) for mesh(field, options)
//   levelset/levelset3.hpp     3D level sets: shapes ("sphere:0,0,0,1", ...), volumes, any callable
//   mesh3d/mesh3d.hpp          the 3D meshing stage (BCC lattice), its lattice and blocks
//   certify/certified.hpp      the proofs' angle bounds and the certification summary
//   post/quality.hpp           the quality report: angles, histogram, radius ratio, area
//   post/mesh_checks.hpp       the mesh invariants, checked from scratch
//   post/optimize.hpp          the monotone optimisation pass (MeshOptions::optimize)
//   post/resolution.hpp        is the spacing fine enough for the input?
//   post/tet_checks.hpp        checks and quality of any tetrahedral mesh
//   report/report.hpp          the reports as text and JSON (to_text, to_json, --report)
//   report/report3d.hpp        the 3D report (Mesh3dReport) as text and JSON
//   pipeline/mesh2d.hpp        mesh(level set, options) → mesh + certified bounds + report
//   pipeline/slices.hpp        a volume's slices: one loaded (load_slice), a range meshed
//   pipeline/mesh3d.hpp        3D: mesh3d(volume file, volume, shape or level set, options) → tetrahedra + report
//   pipeline/options.hpp       options by name: the tables behind the command line's help and parser and Python's keywords
//   pipeline/mesh3d_options.hpp  the 3D options' table (mesh2d.hpp holds the 2D one)
//
// The stages below mesh() (mesh2d/uniform.hpp, mesh2d/graded.hpp,
// mesh2d/lattice.hpp, the generic models mesh2d/generic_square.hpp and
// mesh3d/generic_bcc.hpp) are public too, for callers who drive the pipeline
// themselves; they are not included here.
#pragma once

#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/tet_mesh.hpp"
#include "warpmesh/core/triangle_shape.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/io/writers.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/levelset/levelset3.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/certify/certified.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/post/optimize.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/report/report3d.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/pipeline/slices.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/pipeline/options.hpp"
