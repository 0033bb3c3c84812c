// shapes.hpp — analytic level sets: circle, ellipse, annulus, polar flower,
// rectangle, and their unions, intersections and differences.
//
// Every shape knows, for a segment a→b, the parameters where the segment can
// meet the zero set of f (`crossings`): the roots of a quadratic for conics,
// of a linear equation for rectangle sides.  The zero set of min(f1, f2) or
// max(f1, f2) lies in the union of the zero sets of f1 and f2, so a CSG
// shape's crossings are its operands' crossings.  Shape::cut_parameter picks
// the crossing where f actually changes sign: an exact cut point, computed in
// closed form.  Only shapes without closed-form crossings (the flower, and
// CSG involving one) fall back to bracketed_root.
//
// bounds() is the tight bounding box of {f <= 0}; no margin is added.
//
// range(box) bounds f on a box from the distances to the centre's nearest and
// farthest points of the box (conics), the box's angular extent (flower), or
// interval arithmetic on min / max (rectangle, CSG), widened well beyond the
// rounding of value() (shapes.cpp).
//
// The shape classes below declare the same LevelSet overrides one after the
// other (a repeated declaration block that `duplicates` lists): each is its
// own closed-form geometry, and the repetition is the interface, not logic.
#pragma once

#include <memory>
#include <optional>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/levelset/levelset.hpp"

namespace warpmesh {

class Shape : public LevelSet {
public:
    // Appends every u in (0, 1) at which a + u (b - a) may lie on {f = 0}, and
    // returns true; returns false if the shape cannot enumerate them.
    virtual bool crossings(Vec2 /*a*/, Vec2 /*b*/, std::vector<double>& /*out*/) const { return false; }
    double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const override;
};

// f = |p - c| - r: the signed distance.
class Circle final : public Shape {
public:
    Circle(double cx, double cy, double r);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    bool crossings(Vec2 a, Vec2 b, std::vector<double>& out) const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    double cx_, cy_, r_;
};

// f = min(a, b) (sqrt((x-cx)^2/a^2 + (y-cy)^2/b^2) - 1): zero on the ellipse
// with semi-axes a (along x) and b (along y), and |grad f| = 1 at the
// ends of the minor axis (a signed-distance-like scale).
class Ellipse final : public Shape {
public:
    Ellipse(double cx, double cy, double a, double b);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    bool crossings(Vec2 a, Vec2 b, std::vector<double>& out) const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    double cx_, cy_, a_, b_;
};

// r1 <= |p - c| <= r2, f = max(r1 - |p - c|, |p - c| - r2): the signed distance.
class Annulus final : public Shape {
public:
    Annulus(double cx, double cy, double r1, double r2);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    bool crossings(Vec2 a, Vec2 b, std::vector<double>& out) const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    double cx_, cy_, r1_, r2_;
};

// Polar flower |p - c| <= r(theta) = a + b cos(k theta), with |b| < a and an
// integer k >= 1; f = |p - c| - r(theta).  Area = pi (a^2 + b^2 / 2).
class Flower final : public Shape {
public:
    Flower(double cx, double cy, double a, double b, int k);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    double cx_, cy_, a_, b_;
    int k_;
};

// [x0, x1] x [y0, y1], f = max(x0 - x, x - x1, y0 - y, y - y1).
class Rectangle final : public Shape {
public:
    Rectangle(double x0, double y0, double x1, double y1);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    bool crossings(Vec2 a, Vec2 b, std::vector<double>& out) const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    double x0_, y0_, x1_, y1_;
};

enum class CsgOp { union_, intersection, difference };

// union: min(f1, f2); intersection: max(f1, f2); difference: max(f1, -f2).
// The exact area is known only in the trivial case of operands with disjoint
// bounding boxes (then union = A1 + A2, intersection = 0, difference = A1).
// Both operands are shapes, and an intersection's operands have overlapping
// (or touching) bounding boxes: InputError otherwise.  make_csg (below)
// takes the empty set too.
class Csg final : public Shape {
public:
    Csg(CsgOp op, std::unique_ptr<Shape> first, std::unique_ptr<Shape> second);
    double value(double x, double y) const override;
    Range range(const Box& box) const override;
    Box bounds() const override;
    bool crossings(Vec2 a, Vec2 b, std::vector<double>& out) const override;
    std::optional<double> exact_area() const override;
    std::string describe() const override;

private:
    CsgOp op_;
    std::unique_ptr<Shape> a_, b_;
};

// A CSG operation on shapes that may be the empty set (nullptr), with the
// empty set's algebra: union(A; {}) = union({}; A) = A, intersect(A; {}) =
// intersect({}; A) = {}, diff(A; {}) = A, diff({}; B) = {}; and an
// intersection of shapes whose bounding boxes are disjoint (not merely
// touching) is {}.  Returns nullptr for the empty set, else a Csg (or the one
// non-empty operand).  `why`, if given and still empty, receives the reason
// of the first empty intersection met ("intersect(A;B) is empty: ...").
// The empty set is only recognised this way; a Csg can still have an empty
// region (diff(A; B) with B covering A), which mesh() reports as empty.
std::unique_ptr<Shape> make_csg(CsgOp op, std::unique_ptr<Shape> a, std::unique_ptr<Shape> b,
                                std::string* why = nullptr);

// Parse a shape:
//   circle:cx,cy,r   ellipse:cx,cy,a,b   annulus:cx,cy,r1,r2
//   flower:cx,cy,a,b,k   rect:x0,y0,x1,y1
//   union(S;S[;S...])   intersect(S;S[;S...])   diff(S;S[;S...])   (nestable;
//   diff(A;B;C) = (A - B) - C)
// Sub-expressions are combined by make_csg: an empty part (an intersection
// of shapes with disjoint bounding boxes) is the empty set, e.g.
// union(circle:0,0,5;intersect(circle:20,0,1;circle:-20,0,1)) is the circle.
// Throws InputError naming the string and the problem; a shape that is
// empty as a whole is refused ("the region is empty (...)").
std::unique_ptr<Shape> parse_shape(const std::string& spec);

// The items of a multi-material shapes spec, "TAG=SHAPE;TAG=SHAPE..." (2D
// --shapes and 3D alike), split at the ';' outside parentheses: each tag
// (an integer in 1..65535, each once) and its shape's text, in order.
// Throws InputError naming the spec and the problem (`example` completes
// the message: e.g. "1=circle:0,0,10;2=circle:6,0,8").
std::vector<std::pair<std::int32_t, std::string>> parse_tagged_shapes(const std::string& spec, const char* example);

}  // namespace warpmesh
