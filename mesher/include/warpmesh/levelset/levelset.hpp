// levelset.hpp — what the mesher needs to know about the region to mesh.
//
// Convention: f < 0 inside, f > 0 outside, f = 0 on the boundary.  The region
// meshed is {f <= 0} restricted to the lattice's rectangle.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

struct Box {
    double xmin, ymin, xmax, ymax;
};

// A region tag and a closed box on which region_at gives it (region_in).
struct RegionCell {
    std::int32_t region;
    Box within;
    bool holds(const Box& b) const {
        return b.xmin >= within.xmin && b.xmax <= within.xmax && b.ymin >= within.ymin && b.ymax <= within.ymax;
    }
};

// Bounds lo <= f <= hi on a closed box (lo may be -inf, hi +inf).
struct Range {
    double lo, hi;
};

// Lattice points [i0, i0 + ni) x [j0, j0 + nj) of a Lattice.
struct PointBlock {
    std::int64_t i0, j0, ni, nj;
};

// The lattice a level set is sampled on (the uniform mesher's, mesh2d/lattice.hpp).
// Points (i, j), 0 <= i <= nx, 0 <= j <= ny, at (x0 + i s, y0 + j s); point
// index i + j (nx + 1).  Square (i, j) has corners A = (i, j), B = (i+1, j),
// C = (i, j+1), D = (i+1, j+1) — the generic square's labelling.
struct Lattice {
    double x0 = 0, y0 = 0, s = 1;
    std::int64_t nx = 0, ny = 0;  // number of squares along x and y

    std::int64_t points_x() const { return nx + 1; }
    std::int64_t point_count() const { return (nx + 1) * (ny + 1); }
    std::int64_t index(std::int64_t i, std::int64_t j) const { return i + j * (nx + 1); }
    Vec2 position(std::int64_t i, std::int64_t j) const {
        return {x0 + static_cast<double>(i) * s, y0 + static_cast<double>(j) * s};
    }
};

class LevelSet {
public:
    virtual ~LevelSet() = default;

    // f at a point.  Must be finite wherever the mesher asks.
    virtual double value(double x, double y) const = 0;

    // A rectangle that contains the region {f <= 0} (or, for images, the
    // image's extent).  The default lattice covers it.
    virtual Box bounds() const = 0;
    // True when bounds() is the domain itself (an image's extent) rather than
    // a box around the region: the mesh then fills the lattice over bounds()
    // and may reach its border (pipeline.hpp).  Analytic shapes: false.
    virtual bool bounds_are_domain() const { return false; }

    // The parameter u in (0, 1) of the point a + u (b - a) where f = 0, given
    // f(a) = fa and f(b) = fb of strictly opposite signs.  The default is a
    // bracketed root finder (cut_points.cpp); subclasses override it where the
    // root is known exactly (piecewise-linear images, circles).
    virtual double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const;

    // Fill f at the lattice points of `block` (row-major, ni x nj), with the
    // points' coordinates from Lattice::position and bit for bit the values
    // value() gives there.  The default calls value() (in parallel for large
    // blocks); images override it with a faster loop.
    virtual void sample_block(const Lattice& lattice, const PointBlock& block, std::span<double> out) const;
    // Every lattice point, row-major, (nx+1) x (ny+1).
    void sample(const Lattice& lattice, std::span<double> out) const;

    // Bounds on f over a closed box, used by the graded mesher to skip blocks
    // of the lattice that the level set cannot reach (src/mesh2d/graded/tiles.hpp).  They must
    // hold for the values value() actually computes, rounding included: a
    // block is skipped only when every value there would have had the sign
    // the bound implies.  The default knows nothing: (-inf, +inf).
    virtual Range range(const Box& box) const;

    // Region tag for a triangle with this centroid (label images: the label).
    // Only asked when tags_regions() is true; otherwise every triangle gets 1.
    virtual bool tags_regions() const { return false; }
    virtual std::int32_t region_at(double /*x*/, double /*y*/) const { return 1; }
    // Where the level set can tell cheaply that region_at is one tag on the
    // whole closed box `box`: that tag, and a closed box `within` holding
    // `box` on which the same holds (callers reuse it for the boxes it
    // holds).  Else nullopt: ask region_at per triangle.  It must hold for the
    // centroids the mesher computes from vertices in such a box, rounding
    // included.  Lets the mesher tag the triangles of a run of squares or a
    // coarse leaf with one call.
    virtual std::optional<RegionCell> region_in(const Box& /*box*/) const { return std::nullopt; }

    // Exact area of {f <= 0}, where known (analytic shapes), for tests.
    virtual std::optional<double> exact_area() const { return std::nullopt; }

    virtual std::string describe() const = 0;
};

// The bracketed root finder used by the default cut_parameter: Illinois-type
// regula falsi on g(u) = f(a + u (b - a)), keeping a strict sign bracket so the
// result lies strictly between the two endpoints.
double bracketed_root(const LevelSet& f, Vec2 a, Vec2 b, double fa, double fb);

}  // namespace warpmesh
