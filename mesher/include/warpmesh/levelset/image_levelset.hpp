// image_levelset.hpp — level sets defined by images.
//
// Coordinates: the centre of the pixel in column c, row r (row 0 at the top)
// is the point (x, y) = (x0 + c sx, y0 + (H - 1 - r) sy), by default
// (c, H - 1 - r): pixel units (PixelGeometry; volume slices in millimetres
// give the pixel size and origin).  y points up, so the image appears
// upright and counter-clockwise triangles stay counter-clockwise.  bounds() is
// the pixel-centre box; outside it f is extended as a constant along the
// outward normal (coordinates are clamped into the box).  Internally every
// point is first mapped to pixel coordinates ((x - x0) / sx, (y - y0) / sy),
// which is the identity, bit for bit, for the default geometry.
//
// Both modes give f as the bilinear interpolant of one number per pixel
// centre, so f restricted to an axis-aligned line is piecewise linear with
// knots at the pixel centres.  ImageField::cut_parameter uses this to return the
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
#include <span>
#include <string>
#include <vector>

#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/levelset.hpp"

namespace warpmesh {

enum class ImageMode { threshold, label };

// ", pixel SX x SY, origin (X0, Y0)" for descriptions (PixelGeometry: image.hpp), "" in pixel units.
std::string pixel_geometry_text(const PixelGeometry& geometry);

struct ImageLevelSetOptions {
    ImageMode mode = ImageMode::threshold;
    // threshold mode
    std::optional<double> iso;  // default: maxval / 2
    bool inside_above = true;   // inside = brighter than iso (false: darker)
    // label mode: the region is the pixels whose value is in `labels`, or,
    // with label_nonzero, every pixel that is not 0.
    std::vector<int> labels;
    bool label_nonzero = false;
    // Pixel size and origin (label mode: f stays a distance in pixels, so
    // that the boundary passes midway between 4-adjacent pixels along both
    // axes, whatever their sizes).
    PixelGeometry geometry;
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
    const PixelGeometry& geometry() const { return g_; }
    // f at the centre of pixel (column, row), row 0 at the top.
    double pixel_value(int column, int row) const { return field_[index(column, h_ - 1 - row)]; }

protected:
    ImageField(int w, int h, std::vector<double> field_y_up, PixelGeometry geometry = {});
    std::size_t index(int c, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(c);
    }
    // Level-set coordinates to pixel coordinates (the identity in pixel units).
    double px(double x) const { return (x - g_.x0) / g_.sx; }
    double py(double y) const { return (y - g_.y0) / g_.sy; }
    // f at pixel coordinates (finite).
    double value_px(double x, double y) const;
    // " (pixel sx x sy, origin (x0, y0))", or nothing in pixel units.
    std::string describe_geometry() const;
    // Call once field_ is final: builds the min/max pyramid behind range().
    void build_range_pyramid();
    int w_, h_;
    PixelGeometry g_;
    std::vector<double> field_;
    // pyramid_[k - 1]: per block of 2^(k + 2) x 2^(k + 2) pixels (row-major,
    // ceil(w / 2^(k+2)) blocks per row), the minimum and maximum of field_.
    std::vector<std::vector<std::array<double, 2>>> pyramid_;
};

class ThresholdLevelSet final : public ImageField {
public:
    ThresholdLevelSet(const Image& image, double iso, bool inside_above, PixelGeometry geometry = {});
    // From per-pixel values (y-up, like the field), e.g. a float volume slice.
    ThresholdLevelSet(int w, int h, const std::vector<double>& values_y_up, double iso, bool inside_above,
                      std::string source, PixelGeometry geometry, int maxval = -1);
    std::string describe() const override;

private:
    double iso_;
    bool above_;
    int maxval_;  // -1: from values, not an image
    std::string source_;
};

class LabelLevelSet final : public ImageField {
public:
    LabelLevelSet(const Image& image, std::vector<int> labels, bool nonzero, PixelGeometry geometry = {});
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
// Also for a geometry whose sizes are not positive and finite, or whose
// origin lies more than 2^24 pixels away.
std::unique_ptr<LevelSet> make_image_levelset(const Image& image, const ImageLevelSetOptions& options);

// The same from per-pixel values (y-up: index c + w y), e.g. a volume slice.
// Threshold mode takes them as they are (iso default: midway between their
// minimum and maximum); label mode needs integers in 0..65535 (InputError
// naming the first other value).  maxval >= 0: the values are the samples of
// an image with this maxval (the threshold level set then describes itself
// exactly as make_image_levelset's does).
std::unique_ptr<LevelSet> make_raster_levelset(int w, int h, const std::vector<double>& values_y_up,
                                               const std::string& source, const ImageLevelSetOptions& options,
                                               int maxval = -1);

// Per-pixel values (y-up: index c + w y) as a 16-bit label image (row 0 at
// the top), maxval the largest label (at least 1): what label mode and the
// label-image materials mesh.  Throws InputError naming `source`, `what`
// needs it ("label mode", "--materials"), the first pixel (c, y) whose value
// is not an integer in 0..65535 and whether it is out of range or not an
// integer.
Image label_image(int w, int h, const std::vector<double>& values_y_up, const std::string& source,
                  const std::string& what);

// Throws InputError unless the pixel sizes are positive and finite and the
// origin lies within 2^24 pixels of a w x h image (the coordinates' rounding
// must stay far below a pixel); the default geometry always passes.
void check_pixel_geometry(const PixelGeometry& geometry, int w, int h);

// "3", "51,52", "1000-1035,2000" → the labels (sorted, without duplicates),
// each in 0..65535.  Throws InputError on anything else.
std::vector<int> parse_label_list(const std::string& list);

// The labels a multi-material spec selects (2D and 3D alike): "all" — every
// label present (count[l] > 0) but 0, the background — or a label list
// (parse_label_list).  Throws InputError: no label but 0 with "all", label 0
// in the list, labels not present (named, with those present).  `source`
// names the input ("image 'a.pgm'"), `option` the option as the client
// spells it ("--materials"), `element` the input's element ("pixel").
struct LabelSource {
    std::string source, option, element, container;  // container: "image", "volume"
};
std::vector<int> select_material_labels(std::span<const std::int64_t> count, const std::string& spec, const LabelSource& where);

// Why a sample value is no label, for messages: "label 70000, out of range:
// labels are 0..65535 (16-bit); ..." or "value 2.5, not an integer ...".
// (For a value that is not an integer in 0..65535.)
std::string label_value_problem(double value);

// Label-mode options from a --label argument: "nonzero" or a label list.
ImageLevelSetOptions label_options(const std::string& spec);

}  // namespace warpmesh
