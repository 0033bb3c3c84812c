// shapes.cpp — analytic shapes, their exact cut points, and the shape parser.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string_view>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "shape_syntax.hpp"

namespace warpmesh {
namespace {

constexpr double pi = std::numbers::pi;

std::string num(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
    return std::string(buf, r.ptr);
}

// Appends the real roots u of A u^2 + 2 B u + C = 0, A > 0.  The root of
// larger magnitude is q / A with q = -(B + sign(B) sqrt(D)), which involves
// no cancellation; the other is C / q (the roots' product is C / A).
void quadratic_roots(double A, double B, double C, std::vector<double>& out) {
    if (!(A > 0)) return;  // a degenerate segment
    const double D = B * B - A * C;
    if (!(D >= 0)) return;
    const double sq = std::sqrt(D);
    const double q = B >= 0 ? -(B + sq) : (-B + sq);
    out.push_back(q / A);
    if (q != 0) out.push_back(C / q);
}

// Crossings of the segment a + u d with the circle |p - c| = r:
// |e + u d|^2 = r^2 with e = a - c, i.e. (d.d) u^2 + 2 (e.d) u + (e.e - r^2) = 0.
void circle_roots(Vec2 a, Vec2 b, double cx, double cy, double r, std::vector<double>& out) {
    const double ex = a.x - cx, ey = a.y - cy, dx = b.x - a.x, dy = b.y - a.y;
    quadratic_roots(dx * dx + dy * dy, ex * dx + ey * dy, ex * ex + ey * ey - r * r, out);
}

void require(bool ok, const std::string& what) {
    if (!ok) throw InputError(what);
}
void require_finite(std::initializer_list<double> v, const char* shape) {
    for (double x : v) require(std::isfinite(x), std::string(shape) + ": parameters must be finite numbers");
}

Box box_union(const Box& p, const Box& q) {
    return {std::min(p.xmin, q.xmin), std::min(p.ymin, q.ymin), std::max(p.xmax, q.xmax), std::max(p.ymax, q.ymax)};
}
Box box_intersection(const Box& p, const Box& q) {
    return {std::max(p.xmin, q.xmin), std::max(p.ymin, q.ymin), std::min(p.xmax, q.xmax), std::min(p.ymax, q.ymax)};
}
// Disjoint up to a set of measure zero (touching boxes share at most a segment).
bool boxes_disjoint(const Box& p, const Box& q) {
    return p.xmax <= q.xmin || q.xmax <= p.xmin || p.ymax <= q.ymin || q.ymax <= p.ymin;
}

// Bounds on f over a box.  value() and the bounds are both computed in
// floating point, each within a few units in the last place of the magnitudes
// involved (coordinates, centre, radii); widening by 1e-9 of those magnitudes
// covers both by a factor of ~10^6, so a bound that excludes 0 is never
// contradicted by a computed value.  (A wider range only costs the graded
// mesher some sampling, never correctness.)
double magnitude(const Box& b, std::initializer_list<double> more) {
    double m = std::max({std::abs(b.xmin), std::abs(b.xmax), std::abs(b.ymin), std::abs(b.ymax)});
    for (double v : more) m = std::max(m, std::abs(v));
    return m;
}
Range widened(double lo, double hi, double magnitude) {
    const double e = 1e-9 * magnitude + std::numeric_limits<double>::min();
    return {lo - e, hi + e};
}
// Distances from (cx, cy) to the nearest and the farthest point of a box.
struct Distances {
    double near, far;
};
Distances distances(const Box& b, double cx, double cy) {
    const double nx = std::max({b.xmin - cx, 0.0, cx - b.xmax}), ny = std::max({b.ymin - cy, 0.0, cy - b.ymax});
    const double fx = std::max(std::abs(b.xmin - cx), std::abs(b.xmax - cx)),
                 fy = std::max(std::abs(b.ymin - cy), std::abs(b.ymax - cy));
    return {std::hypot(nx, ny), std::hypot(fx, fy)};
}

}  // namespace

// ---------------------------------------------------------------------------
// Shape: the exact cut point from the candidate crossings.
//
// The crossings t_1 < ... < t_m in (0, 1) split the edge into pieces on which
// f has no zero, hence (f being continuous) a constant sign.  Walking from a,
// the first t_k after which the sign differs from sign(fa) is a zero of f
// where f changes sign — the cut point, in closed form.  A tangential
// crossing (double root, no sign change) is skipped.  If round-off hides the
// sign change (a crossing computed just outside (0, 1), or a near-tangent
// discriminant below 0), we fall back to the bracketed root finder.
double Shape::cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const {
    thread_local std::vector<double> t;
    t.clear();
    if (!crossings(a, b, t)) return bracketed_root(*this, a, b, fa, fb);
    std::erase_if(t, [](double u) { return !(u > 0 && u < 1); });
    std::sort(t.begin(), t.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
    for (std::size_t k = 0; k < t.size(); ++k) {
        const double next = k + 1 < t.size() ? t[k + 1] : 1.0;
        const double g = next == 1.0 ? fb : [&] {
            const double m = 0.5 * (t[k] + next);
            return value(a.x + m * (b.x - a.x), a.y + m * (b.y - a.y));
        }();
        if ((g < 0 && fa > 0) || (g > 0 && fa < 0)) return t[k];
    }
    return bracketed_root(*this, a, b, fa, fb);
}

// ---------------------------------------------------------------------------
// Circle

Circle::Circle(double cx, double cy, double r) : cx_(cx), cy_(cy), r_(r) {
    require_finite({cx, cy, r}, "circle");
    require(r > 0, "circle: radius must be positive (got " + num(r) + ")");
}
double Circle::value(double x, double y) const { return std::sqrt((x - cx_) * (x - cx_) + (y - cy_) * (y - cy_)) - r_; }
Range Circle::range(const Box& b) const {
    const Distances d = distances(b, cx_, cy_);
    return widened(d.near - r_, d.far - r_, magnitude(b, {cx_, cy_, r_, d.far}));
}
Box Circle::bounds() const { return {cx_ - r_, cy_ - r_, cx_ + r_, cy_ + r_}; }
bool Circle::crossings(Vec2 a, Vec2 b, std::vector<double>& out) const {
    circle_roots(a, b, cx_, cy_, r_, out);
    return true;
}
std::optional<double> Circle::exact_area() const { return pi * r_ * r_; }
std::string Circle::describe() const { return "circle:" + num(cx_) + "," + num(cy_) + "," + num(r_); }

// ---------------------------------------------------------------------------
// Ellipse

Ellipse::Ellipse(double cx, double cy, double a, double b) : cx_(cx), cy_(cy), a_(a), b_(b) {
    require_finite({cx, cy, a, b}, "ellipse");
    require(a > 0 && b > 0, "ellipse: semi-axes must be positive (got " + num(a) + ", " + num(b) + ")");
}
double Ellipse::value(double x, double y) const {
    return std::min(a_, b_) * (std::hypot((x - cx_) / a_, (y - cy_) / b_) - 1);
}
// In coordinates scaled by 1/a, 1/b: f = min(a, b) (|q| - 1).
Range Ellipse::range(const Box& b) const {
    const Distances d = distances({(b.xmin - cx_) / a_, (b.ymin - cy_) / b_, (b.xmax - cx_) / a_, (b.ymax - cy_) / b_}, 0, 0);
    const double m = std::min(a_, b_);
    return widened(m * (d.near - 1), m * (d.far - 1), magnitude(b, {cx_, cy_, a_, b_, m * (d.far + 1)}));
}
Box Ellipse::bounds() const { return {cx_ - a_, cy_ - b_, cx_ + a_, cy_ + b_}; }
// In coordinates scaled by 1/a along x and 1/b along y the ellipse is the
// unit circle, and a segment stays a segment with the same parameter u.
bool Ellipse::crossings(Vec2 a, Vec2 b, std::vector<double>& out) const {
    const double ex = (a.x - cx_) / a_, ey = (a.y - cy_) / b_, dx = (b.x - a.x) / a_, dy = (b.y - a.y) / b_;
    quadratic_roots(dx * dx + dy * dy, ex * dx + ey * dy, ex * ex + ey * ey - 1, out);
    return true;
}
std::optional<double> Ellipse::exact_area() const { return pi * a_ * b_; }
std::string Ellipse::describe() const {
    return "ellipse:" + num(cx_) + "," + num(cy_) + "," + num(a_) + "," + num(b_);
}

// ---------------------------------------------------------------------------
// Annulus

Annulus::Annulus(double cx, double cy, double r1, double r2) : cx_(cx), cy_(cy), r1_(r1), r2_(r2) {
    require_finite({cx, cy, r1, r2}, "annulus");
    require(r1 > 0 && r2 > r1, "annulus: radii must satisfy 0 < r1 < r2 (got " + num(r1) + ", " + num(r2) + ")");
}
double Annulus::value(double x, double y) const {
    const double rho = std::sqrt((x - cx_) * (x - cx_) + (y - cy_) * (y - cy_));
    return std::max(r1_ - rho, rho - r2_);
}
Range Annulus::range(const Box& b) const {
    const Distances d = distances(b, cx_, cy_);
    return widened(std::max(r1_ - d.far, d.near - r2_), std::max(r1_ - d.near, d.far - r2_),
                   magnitude(b, {cx_, cy_, r2_, d.far}));
}
Box Annulus::bounds() const { return {cx_ - r2_, cy_ - r2_, cx_ + r2_, cy_ + r2_}; }
bool Annulus::crossings(Vec2 a, Vec2 b, std::vector<double>& out) const {
    circle_roots(a, b, cx_, cy_, r1_, out);
    circle_roots(a, b, cx_, cy_, r2_, out);
    return true;
}
std::optional<double> Annulus::exact_area() const { return pi * (r2_ * r2_ - r1_ * r1_); }
std::string Annulus::describe() const {
    return "annulus:" + num(cx_) + "," + num(cy_) + "," + num(r1_) + "," + num(r2_);
}

// ---------------------------------------------------------------------------
// Flower.  The region is star-shaped about c (r(theta) >= a - |b| > 0), so
// f < 0 exactly inside the curve.  Area = (1/2) int_0^{2 pi} r^2 dtheta
// = (1/2) (2 pi a^2 + b^2 pi) = pi (a^2 + b^2/2), the cross term integrating
// to 0 and cos^2(k theta) to pi for every integer k >= 1.

Flower::Flower(double cx, double cy, double a, double b, int k) : cx_(cx), cy_(cy), a_(a), b_(b), k_(k) {
    require_finite({cx, cy, a, b}, "flower");
    require(a > 0 && std::abs(b) < a, "flower: need a > 0 and |b| < a (got a = " + num(a) + ", b = " + num(b) + ")");
    require(k >= 1, "flower: k must be an integer >= 1");
}
double Flower::value(double x, double y) const {
    const double dx = x - cx_, dy = y - cy_;
    return std::sqrt(dx * dx + dy * dy) - (a_ + b_ * std::cos(k_ * std::atan2(dy, dx)));
}
// f = |p - c| - (a + b cos(k theta)).  A box away from the centre subtends
// an angle below pi, attained at its corners; cos(k theta) over that arc is
// bounded by its values at the ends and by +-1 where the arc contains a
// multiple of 2 pi (resp. an odd multiple of pi).  atan2 and cos round, so the
// arc and the cosine bounds are widened by 1e-9 (their errors are ~1e-16).
Range Flower::range(const Box& b) const {
    const Distances d = distances(b, cx_, cy_);
    double cmin = -1, cmax = 1;
    if (d.near > 0) {
        const double mid = std::atan2(0.5 * (b.ymin + b.ymax) - cy_, 0.5 * (b.xmin + b.xmax) - cx_);
        double lo = 0, hi = 0;
        for (double x : {b.xmin, b.xmax})
            for (double y : {b.ymin, b.ymax}) {
                const double off = std::remainder(std::atan2(y - cy_, x - cx_) - mid, 2 * pi);
                lo = std::min(lo, off), hi = std::max(hi, off);
            }
        const double k = k_, plo = k * (mid + lo - 1e-9), phi = k * (mid + hi + 1e-9);
        if (phi - plo < 2 * pi) {
            const double c0 = std::cos(plo), c1 = std::cos(phi);
            cmin = std::floor((phi - pi) / (2 * pi)) >= std::ceil((plo - pi) / (2 * pi)) ? -1 : std::min(c0, c1) - 1e-9;
            cmax = std::floor(phi / (2 * pi)) >= std::ceil(plo / (2 * pi)) ? 1 : std::max(c0, c1) + 1e-9;
        }
    }
    const double rmin = a_ + std::min(b_ * cmin, b_ * cmax), rmax = a_ + std::max(b_ * cmin, b_ * cmax);
    return widened(d.near - rmax, d.far - rmin, magnitude(b, {cx_, cy_, a_, b_, d.far}));
}
Box Flower::bounds() const {
    const double R = a_ + std::abs(b_);
    return {cx_ - R, cy_ - R, cx_ + R, cy_ + R};
}
std::optional<double> Flower::exact_area() const { return pi * (a_ * a_ + 0.5 * b_ * b_); }
std::string Flower::describe() const {
    return "flower:" + num(cx_) + "," + num(cy_) + "," + num(a_) + "," + num(b_) + "," + std::to_string(k_);
}

// ---------------------------------------------------------------------------
// Rectangle.  f is the max of four affine functions; its zero set lies on the
// four lines x = x0, x = x1, y = y0, y = y1.

Rectangle::Rectangle(double x0, double y0, double x1, double y1) : x0_(x0), y0_(y0), x1_(x1), y1_(y1) {
    require_finite({x0, y0, x1, y1}, "rect");
    require(x0 < x1 && y0 < y1, "rect: need x0 < x1 and y0 < y1 (got " + num(x0) + "," + num(y0) + "," + num(x1) +
                                    "," + num(y1) + ")");
}
double Rectangle::value(double x, double y) const { return std::max({x0_ - x, x - x1_, y0_ - y, y - y1_}); }
Range Rectangle::range(const Box& b) const {
    return widened(std::max({x0_ - b.xmax, b.xmin - x1_, y0_ - b.ymax, b.ymin - y1_}),
                   std::max({x0_ - b.xmin, b.xmax - x1_, y0_ - b.ymin, b.ymax - y1_}), magnitude(b, {x0_, y0_, x1_, y1_}));
}
Box Rectangle::bounds() const { return {x0_, y0_, x1_, y1_}; }
bool Rectangle::crossings(Vec2 a, Vec2 b, std::vector<double>& out) const {
    const double dx = b.x - a.x, dy = b.y - a.y;
    if (dx != 0) out.push_back((x0_ - a.x) / dx), out.push_back((x1_ - a.x) / dx);
    if (dy != 0) out.push_back((y0_ - a.y) / dy), out.push_back((y1_ - a.y) / dy);
    return true;
}
std::optional<double> Rectangle::exact_area() const { return (x1_ - x0_) * (y1_ - y0_); }
std::string Rectangle::describe() const {
    return "rect:" + num(x0_) + "," + num(y0_) + "," + num(x1_) + "," + num(y1_);
}

// ---------------------------------------------------------------------------
// CSG

namespace {
// An intersection is known to be empty when its operands' bounding boxes are
// disjoint; boxes that touch give a valid (if degenerate) box and stay a Csg.
bool empty_intersection(const Shape& a, const Shape& b) {
    const Box i = box_intersection(a.bounds(), b.bounds());
    return !(i.xmin <= i.xmax && i.ymin <= i.ymax);
}
}  // namespace

Csg::Csg(CsgOp op, std::unique_ptr<Shape> first, std::unique_ptr<Shape> second)
    : op_(op), a_(std::move(first)), b_(std::move(second)) {
    require(a_ && b_, "a CSG operation needs two shapes (make_csg takes empty ones)");
    require(op_ != CsgOp::intersection || !empty_intersection(*a_, *b_),
            "intersect: the shapes' bounding boxes are disjoint, so the intersection is empty (make_csg takes it)");
}

std::unique_ptr<Shape> make_csg(CsgOp op, std::unique_ptr<Shape> a, std::unique_ptr<Shape> b, std::string* why) {
    switch (op) {
        case CsgOp::union_:
            if (!a) return b;
            if (!b) return a;
            break;
        case CsgOp::intersection:
            if (!a || !b) return nullptr;
            if (empty_intersection(*a, *b)) {
                if (why && why->empty())
                    *why = "intersect(" + a->describe() + ";" + b->describe() +
                           ") is empty: the bounding boxes of its shapes are disjoint";
                return nullptr;
            }
            break;
        case CsgOp::difference:
            if (!a || !b) return a;
            break;
    }
    return std::make_unique<Csg>(op, std::move(a), std::move(b));
}
double Csg::value(double x, double y) const {
    const double fa = a_->value(x, y), fb = b_->value(x, y);
    switch (op_) {
        case CsgOp::union_: return std::min(fa, fb);
        case CsgOp::intersection: return std::max(fa, fb);
        default: return std::max(fa, -fb);
    }
}
// Interval arithmetic on the operands' (already widened) ranges; min, max and
// negation are exact.
Range Csg::range(const Box& b) const {
    const Range p = a_->range(b), q = b_->range(b);
    switch (op_) {
        case CsgOp::union_: return {std::min(p.lo, q.lo), std::min(p.hi, q.hi)};
        case CsgOp::intersection: return {std::max(p.lo, q.lo), std::max(p.hi, q.hi)};
        default: return {std::max(p.lo, -q.hi), std::max(p.hi, -q.lo)};
    }
}
Box Csg::bounds() const {
    switch (op_) {
        case CsgOp::union_: return box_union(a_->bounds(), b_->bounds());
        case CsgOp::intersection: return box_intersection(a_->bounds(), b_->bounds());
        default: return a_->bounds();
    }
}
bool Csg::crossings(Vec2 a, Vec2 b, std::vector<double>& out) const {
    return a_->crossings(a, b, out) && b_->crossings(a, b, out);
}
std::optional<double> Csg::exact_area() const {
    if (!boxes_disjoint(a_->bounds(), b_->bounds())) return std::nullopt;
    const auto A1 = a_->exact_area(), A2 = b_->exact_area();
    switch (op_) {
        case CsgOp::union_:
            if (A1 && A2) return *A1 + *A2;
            return std::nullopt;
        case CsgOp::intersection: return 0.0;
        default: return A1;
    }
}
std::string Csg::describe() const {
    const char* name = op_ == CsgOp::union_ ? "union" : op_ == CsgOp::intersection ? "intersect" : "diff";
    return std::string(name) + "(" + a_->describe() + ";" + b_->describe() + ")";
}

// ---------------------------------------------------------------------------
// Parser.  Grammar:
//   shape := name ':' number (',' number)*
//          | op '(' shape (';' shape)+ ')'

namespace {

struct Emptiness;
std::unique_ptr<Shape> parse(std::string_view s, Emptiness& empty);

std::unique_ptr<Shape> parse_primitive(std::string_view name, std::string_view args) {
    struct Kind {
        std::string_view name, params;
        std::size_t arity;
    };
    static constexpr Kind kinds[] = {{"circle", "cx,cy,r", 3},       {"ellipse", "cx,cy,a,b", 4},
                                     {"annulus", "cx,cy,r1,r2", 4},  {"flower", "cx,cy,a,b,k", 5},
                                     {"rect", "x0,y0,x1,y1", 4},     {"rectangle", "x0,y0,x1,y1", 4}};
    const Kind* kind = nullptr;
    for (const Kind& k : kinds)
        if (k.name == name) kind = &k;
    if (!kind)
        throw InputError("unknown shape '" + std::string(name) +
                         "' (expected circle, ellipse, annulus, flower, rect, union, intersect or diff)");
    const std::vector<double> v = shape_syntax::parse_numbers(args, name);
    if (v.size() != kind->arity)
        throw InputError(std::string(name) + " takes " + std::to_string(kind->arity) + " numbers (" +
                         std::string(kind->params) + "), got " + std::to_string(v.size()));
    if (name == "circle") return std::make_unique<Circle>(v[0], v[1], v[2]);
    if (name == "ellipse") return std::make_unique<Ellipse>(v[0], v[1], v[2], v[3]);
    if (name == "annulus") return std::make_unique<Annulus>(v[0], v[1], v[2], v[3]);
    if (name == "flower") {
        const double k = v[4];
        if (!(k >= 1 && k <= 1e6 && k == std::floor(k)))
            throw InputError("flower: k must be an integer >= 1 (got " + num(k) + ")");
        return std::make_unique<Flower>(v[0], v[1], v[2], v[3], static_cast<int>(k));
    }
    return std::make_unique<Rectangle>(v[0], v[1], v[2], v[3]);
}

// Why the first empty sub-expression met is empty (for the message when the
// whole shape turns out empty).
struct Emptiness {
    std::string why;
};

std::unique_ptr<Shape> parse_csg(CsgOp op, std::string_view name, std::string_view inner, Emptiness& empty) {
    const std::vector<std::string_view> parts = shape_syntax::split_parts(inner, name);
    // Every part is parsed (and checked) even when the result is already known
    // to be empty.
    std::unique_ptr<Shape> acc = parse(parts[0], empty);
    for (std::size_t i = 1; i < parts.size(); ++i) acc = make_csg(op, std::move(acc), parse(parts[i], empty), &empty.why);
    return acc;
}

std::unique_ptr<Shape> parse(std::string_view s, Emptiness& empty) {
    const shape_syntax::Term t = shape_syntax::split_term(s, "circle:0,0,1");
    if (!t.operation) return parse_primitive(t.name, t.body);
    if (t.name == "union") return parse_csg(CsgOp::union_, t.name, t.body, empty);
    if (t.name == "intersect" || t.name == "intersection") return parse_csg(CsgOp::intersection, t.name, t.body, empty);
    if (t.name == "diff" || t.name == "difference") return parse_csg(CsgOp::difference, t.name, t.body, empty);
    throw InputError("unknown operation '" + std::string(t.name) + "' (expected union, intersect or diff)");
}

}  // namespace

std::unique_ptr<Shape> parse_shape(const std::string& spec) {
    try {
        Emptiness empty;
        std::unique_ptr<Shape> shape = parse(spec, empty);
        if (!shape)
            throw InputError("the region is empty (" + empty.why + "); nothing to mesh");
        return shape;
    } catch (const InputError& e) {
        throw InputError("shape '" + spec + "': " + e.what());
    }
}

std::vector<std::pair<std::int32_t, std::string>> parse_tagged_shapes(const std::string& spec, const char* example) {
    auto bad = [&](const std::string& why) {
        return InputError("bad --shapes '" + spec + "': " + why + " (expected TAG=SHAPE;TAG=SHAPE..., e.g. \"" + example +
                          "\", tags 1..65535)");
    };
    std::vector<std::string> items;
    std::string cur;
    int depth = 0;
    for (char ch : spec) {  // split on ';' outside parentheses (CSG shapes use ';' inside)
        if (ch == '(') ++depth;
        if (ch == ')') --depth;
        if (ch == ';' && depth == 0) items.push_back(cur), cur.clear();
        else cur += ch;
    }
    items.push_back(cur);
    std::vector<std::pair<std::int32_t, std::string>> out;
    std::set<std::int32_t> seen;
    for (const std::string& item : items) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos) throw bad("'" + item + "' has no TAG=");
        const std::string_view t = shape_syntax::trim(std::string_view(item).substr(0, eq));
        int v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (t.empty() || ec != std::errc{} || end != t.data() + t.size() || v < 1 || v > 65535)
            throw bad("tag '" + std::string(t) + "' is not an integer in 1..65535");
        if (!seen.insert(v).second) throw bad("tag " + std::to_string(v) + " is given twice");
        out.emplace_back(v, item.substr(eq + 1));
    }
    return out;
}

}  // namespace warpmesh
