// warpmesh.hpp — the whole public API in one include.
//
//   pipeline.hpp        mesh(level set, options) → mesh + certified bounds + report
//   levelset.hpp        the region to mesh: f < 0 inside (implement it for your own f)
//   shapes.hpp          analytic shapes from strings: "circle:0,0,1", "diff(S;S)", ...
//   image.hpp           read_image / decode_image: PGM, PNG (warpmesh::io)
//   image_levelset.hpp  images → level sets: threshold or labels
//   materials.hpp       multi-material fields (label images, shapes) for mesh(field, options)
//   mesh3d.hpp          3D: level sets, shapes, volumes → tetrahedral meshes (BCC lattice)
//   tet_mesh.hpp        the 3D mesh: vertices, tetrahedra, boundary faces
//   mesh.hpp            the mesh: vertices, triangles, regions, boundary, interfaces
//   certified.hpp       the proofs' angle bounds and the certification summary
//   quality.hpp         the quality report: angles, histogram, radius ratio, area
//   report.hpp          the reports as text and JSON (to_text, to_json, --report)
//   writers.hpp         .vtu .msh .node/.ele .svg .png (warpmesh::io)
//   mesh_checks.hpp     the mesh invariants, checked from scratch
//   optimize.hpp        the monotone optimisation pass (MeshOptions::optimize)
//   resolution.hpp      is the spacing fine enough for the input?
//   errors.hpp          InputError, OutputError
//
// The stages below mesh() (uniform.hpp, graded.hpp, lattice.hpp) are public
// too, for callers who drive the pipeline themselves; they are not included
// here.
#pragma once

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/post/optimize.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/pipeline/options.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/pipeline/slices.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/io/writers.hpp"
