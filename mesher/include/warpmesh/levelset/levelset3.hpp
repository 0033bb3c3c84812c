// levelset3.hpp — level sets in 3D: f(x, y, z) < 0 inside, > 0 outside, 0
// on the boundary; what the 3D mesher (mesh3d/mesh3d.hpp) meshes.  Any
// callable (FunctionLevelSet3), the analytic shapes (parse_shape3) and the
// level set of a volume (make_volume_levelset3).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "warpmesh/core/memory.hpp"
#include "warpmesh/core/tet_mesh.hpp"            // Point3
#include "warpmesh/levelset/image_levelset.hpp"  // ImageLevelSetOptions: the volume modes

namespace warpmesh {

struct Volume;  // volume.hpp

struct Box3 {
    double xmin, ymin, zmin, xmax, ymax, zmax;
};

class LevelSet3 {
public:
    virtual ~LevelSet3() = default;
    // f at a point; finite wherever the mesher asks.
    virtual double value(double x, double y, double z) const = 0;
    // A box containing the region {f <= 0} (volumes: the volume's extent).
    // The lattice covers it with a margin (lattice3_for).
    virtual Box3 bounds() const = 0;
    // The box the input is defined on, where it cuts the region off (a
    // volume: the hull of its voxel centres, whose faces close a region that
    // reaches the volume's edge); nullopt: none (shapes, functions).  The
    // mesh's boundary faces on it are tagged boundary_domain, as 2D tags the
    // image's border.
    virtual std::optional<Box3> domain() const { return std::nullopt; }
    // The parameter u in (0, 1) of a zero of f on a + u (b − a), given f(a) =
    // fa and f(b) = fb of strictly opposite signs.  Default: bracketed_root3.
    virtual double cut_parameter(Point3 a, Point3 b, double fa, double fb) const;
    // The thinnest feature of the region (a sphere's radius, a torus's tube
    // radius, half a box's smallest side; volumes: the largest inscribed
    // distance of the region — for a label volume only while it is within
    // the distance band, else 0), for the coarse-spacing warning; 0: unknown.
    virtual double feature_size() const { return 0; }
    // The input's own resolution (volumes: the smallest voxel spacing; 0 for
    // analytic level sets): the coarse-spacing warning never suggests a
    // spacing below it and is silent at a spacing at or below it.
    virtual double resolution() const { return 0; }
    // Exact volume of {f <= 0} where known (analytic shapes), for tests.
    virtual std::optional<double> exact_volume() const { return std::nullopt; }
    // The volume the input itself gives the region, where it gives one
    // (label volumes: the region's voxels times a voxel's volume); the 3D
    // pipeline warns when the mesh's volume is far from it.
    virtual std::optional<double> reference_volume() const { return std::nullopt; }
    virtual std::string describe() const = 0;
    // The level set of a part of a volume (Volume::is_part): whether f was
    // asked where its value depends on voxels outside the part (it was then
    // answered wrongly): the caller's part was too small.
    virtual bool read_outside_part() const { return false; }
};

// Illinois regula falsi with a bisection step every eighth iteration, to
// convergence (the bracket shrinks to a few ulps or f = 0 is hit), keeping a
// strict sign bracket: the result lies in (0, 1).  The same root finder as
// 2D's bracketed_root (one implementation, src/core/root_finder.hpp).
double bracketed_root3(const LevelSet3& f, Point3 a, Point3 b, double fa, double fb);

// A level set from any callable (tests, Python): f and a box around the region.
class FunctionLevelSet3 final : public LevelSet3 {
public:
    FunctionLevelSet3(std::function<double(double, double, double)> f, Box3 box, std::string name = "function");
    double value(double x, double y, double z) const override { return f_(x, y, z); }
    Box3 bounds() const override { return box_; }
    std::string describe() const override { return name_; }

private:
    std::function<double(double, double, double)> f_;
    Box3 box_;
    std::string name_;
};

// Analytic shapes, the 3D siblings of shapes.hpp, with the same syntax:
//   sphere:cx,cy,cz,r            f = |p − c| − r
//   ellipsoid:cx,cy,cz,a,b,c     f = min(a,b,c) (|((x−cx)/a, (y−cy)/b, (z−cz)/c)| − 1)
//   torus:cx,cy,cz,R,r           axis z: f = |(ρ − R, z − cz)| − r, ρ = |(x−cx, y−cy)|, 0 < r < R
//   box:x0,y0,z0,x1,y1,z1        f = max(x0 − x, x − x1, y0 − y, ...)
//   cylinder:x0,y0,z0,x1,y1,z1,r the capped cylinder of radius r around the
//                                segment p0 p1: f = max(dist to the axis − r,
//                                |t − L/2| − L/2), t the position along the axis
//   union(S;S[;S...])  intersect(S;S[;S...])  diff(S;S[;S...])  (nestable)
// union = min, intersection = max, difference = max(f1, −f2).  Throws
// InputError naming the string and the problem (an unknown shape, a wrong
// number of parameters, a non-positive radius or size, an intersection of
// shapes whose boxes are disjoint: the region is empty).
std::unique_ptr<LevelSet3> parse_shape3(const std::string& spec);

// The level set of a volume (volume.hpp's geometry: physical coordinates in
// mm, or voxel indices for a non-physical volume), in the modes of 2D images
// (ImageLevelSetOptions; its `geometry` is ignored, the volume has its own):
//   threshold  f = iso − G (inside_above, the default) or G − iso, G the
//              trilinear interpolant of the voxel values; iso defaults to the
//              middle of the value range;
//   label      the region is the voxels whose value is in `labels` (or every
//              non-zero voxel with label_nonzero); f is the signed distance
//              between voxel centres, d_out − h/2 outside and −(d_in − h/2)
//              inside (d the exact Euclidean distance, spacing-weighted, to the
//              nearest voxel centre of the other class; h/2 puts the boundary
//              midway between a voxel inside and its 6-neighbour outside along
//              each axis), interpolated trilinearly.  The band contract:
//              with cap = band × the largest spacing, a voxel's value is
//              clamp(±(d − h/2), −cap, cap), exact (the transform's value,
//              as a 4-byte float) wherever |f| < cap and ±cap beyond, so its
//              sign is the voxel's class everywhere and clamping never raises
//              the field's Lipschitz constant (|clamp a − clamp b| <= |a − b|).
//              What the mesher reads: the sign at every lattice point, and
//              f along cut edges for the cut points (warping reads the cut
//              points, not f) — on cut_parameter's cubic path only the voxel
//              cell where f changes sign, whose corners lie within a voxel
//              of the boundary, inside the band (>= 2 voxels); its fallback
//              iterates on f itself, clamped values included (they are f).  Stored on the region's bounding box
//              plus `band` voxels (farther voxels get ±cap without being
//              stored); the distances come from the voxels within cap + h of
//              each voxel (banded_distance, volume_levelset3.cpp), so a
//              voxel's value depends only on the labels within that reach.
// The region is cut off at the hull of the voxel centres (f = max(the
// interpolant at the nearest point of the hull, the box distance to the hull
// in f's units): continuous, and a region reaching the volume's edge is
// closed there by boundary faces on the level set).  Memory: refused
// (InputError naming the memory limit) before anything is allocated when the field would take the resident memory above max_memory.
// Throws InputError for label mode on non-integer values, labels absent from
// the volume (an empty region), a volume less than 2 voxels along an axis.
struct LabelRegionFacts;
struct VolumeLevelSet3Options {
    ImageLevelSetOptions mode;  // threshold / label, iso, inside_above, labels, label_nonzero
    int band = 4;               // voxels of exact distance around the boundary (label mode), >= 2
    std::uint64_t max_memory = default_max_memory;
    // Label mode on a part of a volume (Volume::is_part): the whole region's
    // facts (merge_label_facts), required there, refused on a whole volume.
    const LabelRegionFacts* whole = nullptr;
};
std::unique_ptr<LevelSet3> make_volume_levelset3(const Volume& volume, const VolumeLevelSet3Options& options);
// The same, releasing the volume's samples (label mode: as soon as the
// region's mask is read from them, before the distance field is built) for
// a caller that needs only its geometry afterwards.
std::unique_ptr<LevelSet3> make_volume_levelset3(Volume&& volume, const VolumeLevelSet3Options& options);

// One region of a label volume in parts (pipeline/mesh3d.hpp, "Blocks that
// read only their part").  A voxel's value in label mode depends only on the
// labels within label_reach(spacing, band)[a] voxels along index axis a:
// the sources within cap + 2c (cap = band × the largest spacing, c half the
// smallest) and their 6-neighbours.  Three facts are the whole region's: its
// voxel box (bounds(), where the lattice lies, and the stored box: the
// band's voxels beyond it are +cap), the field's minimum (cut_parameter's
// switch between the cubic path and the root finder) and the inscribed
// distance (feature_size), with the voxel count (reference_volume).  So a
// reduction finds them before any block is meshed: each part of a tiling of
// the volume (its own voxels [owned_lo, owned_hi), read with label_reach
// more around them) gives them for its own voxels (label_part_facts),
// merge_label_facts combines the parts' — the region's box, the sum, the
// minimum and the maximum — and the level set of any part of the volume
// (VolumeLevelSet3Options::whole) then has, wherever it reads voxels at
// least label_reach from the part's cut faces, the whole volume's values to
// the last bit; elsewhere it flags read_outside_part.  (The minimum is
// carried rather than replaced by the data-independent −cap: where the
// region is thinner than the band the two send different cut edges to the
// root finder, and the cut points round differently.)
struct LabelRegionFacts {
    // What they are of: the labels (their list's text), band and voxel size
    // (`of`); the whole volume's voxels; the voxels [owned_lo, owned_hi) the
    // facts count (merged: the whole volume).  Facts of different ones do
    // not merge.
    std::string labels, of;
    std::array<std::int64_t, 3> whole{0, 0, 0}, owned_lo{0, 0, 0}, owned_hi{0, 0, 0};
    // The region's voxels among them: their box [lo, hi] (lo > hi: none),
    // count, the field's minimum at them (a stored 4-byte float) and their
    // largest inscribed distance (+inf: one is deeper than the band).
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{-1, -1, -1};
    std::int64_t voxels = 0;
    double lowest = 0, deepest = 0;
    std::vector<std::uint8_t> seen;  // per listed label (ImageLevelSetOptions::labels): whether a voxel has it
    bool operator==(const LabelRegionFacts&) const = default;
};
std::array<std::int64_t, 3> label_reach(const std::array<double, 3>& spacing, int band);
// The facts of the part's voxels [owned_lo, owned_hi) (whole-volume indices;
// `part` a Volume::is_part, or the whole volume).  Throws InputError in
// threshold mode, for non-integer values, and unless the part holds
// label_reach voxels around them (within the whole volume).
LabelRegionFacts label_part_facts(const Volume& part, const VolumeLevelSet3Options& options, const std::array<std::int64_t, 3>& owned_lo,
                                  const std::array<std::int64_t, 3>& owned_hi);
// The whole region's facts from its parts'.  Throws InputError, naming what
// is wrong, unless the parts are of one labels, band, voxel size and volume
// and tile the volume exactly once, and (as make_volume_levelset3) for an
// empty region or a listed label no voxel has.
LabelRegionFacts merge_label_facts(std::span<const LabelRegionFacts> parts, const std::string& source);

}  // namespace warpmesh
