// materials3.hpp — multi-material fields in 3D: which material owns each
// point of space, and where the interface between two materials crosses a
// segment.  What the multi-material 3D mesher (mesh3d/mesh3d.hpp:
// mesh_bcc_materials) meshes; the 3D sibling of mesh2d/materials.hpp's
// MaterialField, with the same model.
//
// Model.  Materials are numbered 0 .. count()-1; material 0 is the
// background (label volumes: every voxel not selected; shapes: outside every
// shape).  Each material m has a function phi_m, negative inside it; the
// material at a point is the one whose phi is smallest (an exact tie: see
// each field).  The interface between materials a and b is where phi_a =
// phi_b.  Beyond the field's domain (a volume: outside the hull of its voxel
// centres) the point is `outside_material`, which no mesh contains.
//
// Label numbers do not matter.  No rule reads a label's value, only whether
// two points' materials are equal and whether a material is the background;
// ties are broken by geometry.  Renumbering a volume's labels (0 stays 0)
// gives the same mesh with its region tags renumbered.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "warpmesh/core/memory.hpp"
#include "warpmesh/levelset/levelset3.hpp"  // Box3, Point3

namespace warpmesh {

struct Volume;  // volume.hpp

inline constexpr int outside_material = -1;

class MaterialField3 {
public:
    virtual ~MaterialField3() = default;

    virtual int count() const = 0;              // materials, background included (<= 65535)
    virtual std::int32_t tag(int m) const = 0;  // region tag: the label value; background 0
    virtual std::string name(int m) const = 0;  // "label_41", "background"
    // A box containing every material but the background (the lattice covers
    // it with a margin; with the background kept, a volume's whole hull).
    virtual Box3 bounds() const = 0;
    // The box the field is defined on (outside_material beyond it; a volume:
    // the hull of its voxel centres), as LevelSet3::domain; nullopt: none.
    virtual std::optional<Box3> domain() const { return std::nullopt; }
    virtual std::string describe() const = 0;

    // The material at p (0 .. count()-1), or outside_material.
    virtual int material_at(Point3 p) const = 0;
    // The parameter u in (0, 1) of the point a + u (b − a) where the
    // interface between ma (the material at a) and mb (at b, mb != ma) crosses
    // the segment; one of them may be outside_material (then: where the
    // segment leaves the domain).
    virtual double cut_parameter(Point3 a, Point3 b, int ma, int mb) const = 0;

    // The volume the input gives material m, where it gives one (label
    // volumes: its voxel count times a voxel's volume), for the report.
    virtual std::optional<double> reference_volume(int /*m*/) const { return std::nullopt; }
    // The input's own resolution (volumes: the smallest voxel spacing; 0 for
    // shapes), as LevelSet3::resolution.
    virtual double resolution() const { return 0; }
    // A field of a part of a volume (Volume::is_part): whether any material
    // or cut was asked of a point whose voxels lie outside the part (it was
    // then answered as the background): the caller's region was too small.
    virtual bool read_outside_part() const { return false; }
};

// The materials of a label volume (volume.hpp's geometry: millimetres, or
// voxel indices for a non-physical volume).  `spec`: "all" (every label
// present except 0, which is the background) or a label list as
// parse_label_list reads it ("3,41,42", "1000-1035"); every other voxel joins
// the background.
//
// phi_m, in voxel units (so that an interface passes midway between
// 6-adjacent voxels of different labels whatever the voxel sizes, as in 2D):
// at a voxel centre c, D_m(c) = −(d − 1/2) if c has label m, d the distance
// (in voxel steps) to the nearest voxel of another label, else d − 1/2, d
// the distance to the nearest voxel of label m; both distances are taken in
// c's 3 x 3 x 3 neighbourhood (1, √2 or √3) and are 2 where it has no such
// voxel.  phi_m is D_m's trilinear interpolant.  The material at a point is
// chosen among the labels at the eight corners of its voxel cell (a label
// absent from them has phi >= 1/2 in the whole cell); a tie goes to the tied
// material of the nearest corner, equally near ones by the corners' order
// (z, then y, then x, the highest first) — geometry, not label values.  Cut
// points are zeros of phi_a − phi_b, cubic on each voxel cell the segment
// crosses, found to the last bits.  The domain is the hull of the voxel
// centres; a segment leaving it is cut where it crosses the hull's face.
//
// Throws InputError: label 0 in the list, labels absent from the volume
// (named), no label at all, non-integer values or values outside 0..65535, a
// volume less than 2 voxels along an axis, a field above max_memory (2 bytes
// a voxel).
std::unique_ptr<MaterialField3> make_volume_materials3(const Volume& volume, const std::string& spec,
                                                       std::uint64_t max_memory = default_max_memory);

// Analytic materials: "1=sphere:0,0,0,1;2=box:-1,-1,-1,0,0,0" (parse_shape3's
// syntax after '='; tags 1..65535, each once).  A later shape wins where
// shapes overlap; outside all of them: background (tag 0).  With f_k the
// shapes' level sets, phi_m = max(f_m, −f_k for every later k), background
// phi_0 = max(−f_k); an exact tie goes to the later shape.  Throws
// InputError naming the part of the spec at fault.
std::unique_ptr<MaterialField3> parse_material_shapes3(const std::string& spec);

}  // namespace warpmesh
