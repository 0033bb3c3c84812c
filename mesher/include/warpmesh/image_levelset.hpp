// image_levelset.hpp — level sets defined by images.
//
// Coordinates: the centre of the pixel in column c, row r (row 0 at the top)
// is the point (x, y) = (c, H - 1 - r).  y points up, so the image appears
// upright and counter-clockwise triangles stay counter-clockwise.  bounds() is
// the pixel-centre box [0, W-1] x [0, H-1]; outside it f is extended as a
// constant along the outward normal (coordinates are clamped into the box).
//
// Both modes give f as the bilinear interpolant of one number per pixel
// centre, so f restricted to an axis-aligned line is piecewise linear with
// knots at the integers.  ImageField::cut_parameter uses this to return the
// exact zero of f on a lattice edge, not an iterate.
//
//   threshold  f = V - I (inside = above: pixels brighter than V are inside)
//              f = I - V (inside = below), I the bilinear interpolant of the
//              pixel values and V the iso value.
//   label      the region is the set of pixels whose value is in a label set;
//              per pixel, f = -(d_out - 1/2) inside and f = d_in - 1/2
//              outside, where d_out / d_in is the exact Euclidean distance to
//              the nearest pixel centre outside / inside the region.  See
//              image_levelset.cpp for why this gives a smooth boundary.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/image.hpp"
#include "warpmesh/levelset.hpp"

namespace warpmesh {

enum class ImageMode { threshold, label };

struct ImageLevelSetOptions {
    ImageMode mode = ImageMode::threshold;
    // threshold mode
    std::optional<double> iso;  // default: maxval / 2
    bool inside_above = true;   // inside = brighter than iso (false: darker)
    // label mode: the region is the pixels whose value is in `labels`, or,
    // with label_nonzero, every pixel that is not 0.
    std::vector<int> labels;
    bool label_nonzero = false;
};

// Bilinear interpolant of per-pixel values `field` (stored y-up: index
// c + W * y, y = H - 1 - row).  The base of both image modes.
class ImageField : public LevelSet {
public:
    double value(double x, double y) const override;
    Box bounds() const override;
    bool bounds_are_domain() const override { return true; }
    // Exact zero of the piecewise-linear restriction of f to an axis-aligned
    // edge (bracketed_root for any other segment).
    double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const override;
    void sample_block(const Lattice& lattice, const PointBlock& block, std::span<double> out) const override;
    // The interpolant on a box is a convex combination of the pixel values
    // around it: their minimum and maximum bound it (min/max pyramid).
    Range range(const Box& box) const override;

    int width() const { return w_; }
    int height() const { return h_; }
    // f at the centre of pixel (column, row), row 0 at the top.
    double pixel_value(int column, int row) const { return field_[index(column, h_ - 1 - row)]; }

protected:
    ImageField(int w, int h, std::vector<double> field_y_up);
    std::size_t index(int c, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(c);
    }
    // Call once field_ is final: builds the min/max pyramid behind range().
    void build_range_pyramid();
    int w_, h_;
    std::vector<double> field_;
    // pyramid_[k - 1]: per block of 2^(k + 2) x 2^(k + 2) pixels (row-major,
    // ceil(w / 2^(k+2)) blocks per row), the minimum and maximum of field_.
    std::vector<std::vector<std::array<double, 2>>> pyramid_;
};

class ThresholdLevelSet final : public ImageField {
public:
    ThresholdLevelSet(const Image& image, double iso, bool inside_above);
    std::string describe() const override;

private:
    double iso_;
    bool above_;
    int maxval_;
    std::string source_;
};

class LabelLevelSet final : public ImageField {
public:
    LabelLevelSet(const Image& image, std::vector<int> labels, bool nonzero);
    std::string describe() const override;
    // Triangles are tagged with the label of the nearest pixel in the region.
    bool tags_regions() const override { return true; }
    std::int32_t region_at(double x, double y) const override;
    std::optional<RegionCell> region_in(const Box& box) const override;

private:
    std::vector<std::uint16_t> label_;      // y-up, like field_
    std::vector<std::uint8_t> inside_;      // pixel is in the region
    // Per pixel cell (lower-left pixel index): the label of the pixels around
    // it that are in the region, if there are some and they share one label,
    // else -1.  Lets region_at answer most triangles with one load.
    std::vector<std::int32_t> cell_label_;
    std::vector<std::uint32_t> nearest_in_; // index of the nearest region pixel (itself when inside)
    std::vector<int> labels_;
    bool nonzero_;
    std::string source_;
};

// The level set for an image and options.  Throws InputError for a non-finite
// iso value, an empty or out-of-range label list, or labels absent from the
// image (the message lists some labels that are present).
std::unique_ptr<LevelSet> make_image_levelset(const Image& image, const ImageLevelSetOptions& options);

// "3", "51,52", "1000-1035,2000" → the labels (sorted, without duplicates),
// each in 0..65535.  Throws InputError on anything else.
std::vector<int> parse_label_list(const std::string& list);

// Label-mode options from a --label argument: "nonzero" or a label list.
ImageLevelSetOptions label_options(const std::string& spec);

}  // namespace warpmesh
