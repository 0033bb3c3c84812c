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

#include "warpmesh/mesh.hpp"

namespace warpmesh {

struct Box {
    double xmin, ymin, xmax, ymax;
};

struct Lattice;

class LevelSet {
public:
    virtual ~LevelSet() = default;

    // f at a point.  Must be finite wherever the mesher asks.
    virtual double value(double x, double y) const = 0;

    // A rectangle that contains the region {f <= 0} (or, for images, the
    // image's extent).  The default lattice covers it.
    virtual Box bounds() const = 0;

    // The parameter u in (0, 1) of the point a + u (b - a) where f = 0, given
    // f(a) = fa and f(b) = fb of strictly opposite signs.  The default is a
    // bracketed root finder (cut_points.cpp); subclasses override it where the
    // root is known exactly (piecewise-linear images, circles).
    virtual double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const;

    // Fill f at every lattice point (row-major, (nx+1) x (ny+1)).  The default
    // calls value() in parallel; images override it with a faster loop.
    virtual void sample(const Lattice& lattice, std::span<double> out) const;

    // Region tag for a triangle with this centroid (label images: the label).
    // Only asked when tags_regions() is true; otherwise every triangle gets 1.
    virtual bool tags_regions() const { return false; }
    virtual std::int32_t region_at(double /*x*/, double /*y*/) const { return 1; }

    // Exact area of {f <= 0}, where known (analytic shapes), for tests.
    virtual std::optional<double> exact_area() const { return std::nullopt; }

    virtual std::string describe() const = 0;
};

// The bracketed root finder used by the default cut_parameter: Illinois-type
// regula falsi on g(u) = f(a + u (b - a)), keeping a strict sign bracket so the
// result lies strictly between the two endpoints.
double bracketed_root(const LevelSet& f, Vec2 a, Vec2 b, double fa, double fb);

}  // namespace warpmesh
