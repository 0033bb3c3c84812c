// shapes3.cpp — analytic 3D level sets, their CSG, and the shape parser
// (mesh3d.hpp), the 3D siblings of shapes.cpp with the same syntax.
//
// Every primitive's f is a signed distance or a scaled one (the ellipsoid:
// min(a, b, c) times the normalised radius minus 1, a distance near the
// minor axes), so the boundary fidelity the report measures is in length
// units.  Cut points use the bracketed root finder to convergence.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string_view>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/levelset/levelset3.hpp"
#include "core/root_finder.hpp"
#include "shape_syntax.hpp"

namespace warpmesh {

double bracketed_root3(const LevelSet3& f, Point3 a, Point3 b, double fa, double fb) {
    return bracketed_root_of(
        [&](double u) { return f.value(a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z)); }, fa, fb);
}

double LevelSet3::cut_parameter(Point3 a, Point3 b, double fa, double fb) const {
    return bracketed_root3(*this, a, b, fa, fb);
}

FunctionLevelSet3::FunctionLevelSet3(std::function<double(double, double, double)> f, Box3 box, std::string name)
    : f_(std::move(f)), box_(box), name_(std::move(name)) {
    if (!f_) throw InputError("FunctionLevelSet3: no function");
    if (!(box.xmin < box.xmax && box.ymin < box.ymax && box.zmin < box.zmax) ||
        !std::isfinite(box.xmin + box.xmax + box.ymin + box.ymax + box.zmin + box.zmax))
        throw InputError("FunctionLevelSet3: the box must be finite with min < max on every axis");
}

namespace {

constexpr double pi = std::numbers::pi;

std::string num(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}
void require(bool ok, const std::string& what) {
    if (!ok) throw InputError(what);
}

class Sphere final : public LevelSet3 {
public:
    Sphere(double cx, double cy, double cz, double r) : c_{cx, cy, cz}, r_(r) {
        require(r > 0, "sphere: the radius must be positive (got " + num(r) + ")");
    }
    double value(double x, double y, double z) const override {
        return std::sqrt((x - c_.x) * (x - c_.x) + (y - c_.y) * (y - c_.y) + (z - c_.z) * (z - c_.z)) - r_;
    }
    Box3 bounds() const override { return {c_.x - r_, c_.y - r_, c_.z - r_, c_.x + r_, c_.y + r_, c_.z + r_}; }
    double feature_size() const override { return r_; }
    std::optional<double> exact_volume() const override { return 4.0 / 3.0 * pi * r_ * r_ * r_; }
    std::string describe() const override {
        return "sphere:" + num(c_.x) + "," + num(c_.y) + "," + num(c_.z) + "," + num(r_);
    }

private:
    Point3 c_;
    double r_;
};

class Ellipsoid final : public LevelSet3 {
public:
    Ellipsoid(double cx, double cy, double cz, double a, double b, double c) : c_{cx, cy, cz}, a_{a, b, c} {
        require(a > 0 && b > 0 && c > 0, "ellipsoid: the semi-axes must be positive");
    }
    double value(double x, double y, double z) const override {
        const double u = (x - c_.x) / a_[0], v = (y - c_.y) / a_[1], w = (z - c_.z) / a_[2];
        return std::min({a_[0], a_[1], a_[2]}) * (std::sqrt(u * u + v * v + w * w) - 1);
    }
    Box3 bounds() const override {
        return {c_.x - a_[0], c_.y - a_[1], c_.z - a_[2], c_.x + a_[0], c_.y + a_[1], c_.z + a_[2]};
    }
    double feature_size() const override { return std::min({a_[0], a_[1], a_[2]}); }
    std::optional<double> exact_volume() const override { return 4.0 / 3.0 * pi * a_[0] * a_[1] * a_[2]; }
    std::string describe() const override {
        return "ellipsoid:" + num(c_.x) + "," + num(c_.y) + "," + num(c_.z) + "," + num(a_[0]) + "," + num(a_[1]) +
               "," + num(a_[2]);
    }

private:
    Point3 c_;
    std::array<double, 3> a_;
};

class Torus final : public LevelSet3 {
public:
    Torus(double cx, double cy, double cz, double R, double r) : c_{cx, cy, cz}, R_(R), r_(r) {
        require(r > 0 && R > r, "torus: needs 0 < r < R (got R = " + num(R) + ", r = " + num(r) + ")");
    }
    double value(double x, double y, double z) const override {
        const double rho = std::hypot(x - c_.x, y - c_.y);
        return std::hypot(rho - R_, z - c_.z) - r_;
    }
    Box3 bounds() const override {
        const double e = R_ + r_;
        return {c_.x - e, c_.y - e, c_.z - r_, c_.x + e, c_.y + e, c_.z + r_};
    }
    double feature_size() const override { return r_; }
    std::optional<double> exact_volume() const override { return 2 * pi * pi * R_ * r_ * r_; }
    std::string describe() const override {
        return "torus:" + num(c_.x) + "," + num(c_.y) + "," + num(c_.z) + "," + num(R_) + "," + num(r_);
    }

private:
    Point3 c_;
    double R_, r_;
};

class BoxShape final : public LevelSet3 {
public:
    explicit BoxShape(Box3 b) : b_(b) {
        require(b.xmin < b.xmax && b.ymin < b.ymax && b.zmin < b.zmax, "box: needs x0 < x1, y0 < y1 and z0 < z1");
    }
    double value(double x, double y, double z) const override {
        return std::max({b_.xmin - x, x - b_.xmax, b_.ymin - y, y - b_.ymax, b_.zmin - z, z - b_.zmax});
    }
    Box3 bounds() const override { return b_; }
    double feature_size() const override {
        return 0.5 * std::min({b_.xmax - b_.xmin, b_.ymax - b_.ymin, b_.zmax - b_.zmin});
    }
    std::optional<double> exact_volume() const override {
        return (b_.xmax - b_.xmin) * (b_.ymax - b_.ymin) * (b_.zmax - b_.zmin);
    }
    std::string describe() const override {
        return "box:" + num(b_.xmin) + "," + num(b_.ymin) + "," + num(b_.zmin) + "," + num(b_.xmax) + "," +
               num(b_.ymax) + "," + num(b_.zmax);
    }

private:
    Box3 b_;
};

class Cylinder final : public LevelSet3 {
public:
    Cylinder(Point3 p0, Point3 p1, double r) : p0_(p0), p1_(p1), r_(r) {
        d_ = {p1.x - p0.x, p1.y - p0.y, p1.z - p0.z};
        len_ = std::sqrt(d_.x * d_.x + d_.y * d_.y + d_.z * d_.z);
        require(r > 0 && len_ > 0, "cylinder: needs a radius > 0 and two distinct axis end points");
        d_ = {d_.x / len_, d_.y / len_, d_.z / len_};
    }
    double value(double x, double y, double z) const override {
        const double px = x - p0_.x, py = y - p0_.y, pz = z - p0_.z;
        const double t = px * d_.x + py * d_.y + pz * d_.z;
        const double qx = px - t * d_.x, qy = py - t * d_.y, qz = pz - t * d_.z;
        return std::max(std::sqrt(qx * qx + qy * qy + qz * qz) - r_, std::abs(t - 0.5 * len_) - 0.5 * len_);
    }
    // The box of the two end discs: along each axis the disc extends r sin(angle to the axis).
    Box3 bounds() const override {
        const auto ext = [&](double dk) { return r_ * std::sqrt(std::max(0.0, 1 - dk * dk)); };
        const double ex = ext(d_.x), ey = ext(d_.y), ez = ext(d_.z);
        return {std::min(p0_.x, p1_.x) - ex, std::min(p0_.y, p1_.y) - ey, std::min(p0_.z, p1_.z) - ez,
                std::max(p0_.x, p1_.x) + ex, std::max(p0_.y, p1_.y) + ey, std::max(p0_.z, p1_.z) + ez};
    }
    double feature_size() const override { return std::min(r_, 0.5 * len_); }
    std::optional<double> exact_volume() const override { return pi * r_ * r_ * len_; }
    std::string describe() const override {
        return "cylinder:" + num(p0_.x) + "," + num(p0_.y) + "," + num(p0_.z) + "," + num(p1_.x) + "," +
               num(p1_.y) + "," + num(p1_.z) + "," + num(r_);
    }

private:
    Point3 p0_, p1_, d_;
    double r_, len_;
};

enum class Op { union_, intersection, difference };

// union: min(f1, f2); intersection: max(f1, f2); difference: max(f1, −f2).
class Csg3 final : public LevelSet3 {
public:
    Csg3(Op op, std::unique_ptr<LevelSet3> a, std::unique_ptr<LevelSet3> b) : op_(op), a_(std::move(a)), b_(std::move(b)) {}
    double value(double x, double y, double z) const override {
        const double fa = a_->value(x, y, z), fb = b_->value(x, y, z);
        switch (op_) {
            case Op::union_: return std::min(fa, fb);
            case Op::intersection: return std::max(fa, fb);
            default: return std::max(fa, -fb);
        }
    }
    Box3 bounds() const override {
        const Box3 p = a_->bounds(), q = b_->bounds();
        if (op_ == Op::difference) return p;
        if (op_ == Op::intersection)
            return {std::max(p.xmin, q.xmin), std::max(p.ymin, q.ymin), std::max(p.zmin, q.zmin),
                    std::min(p.xmax, q.xmax), std::min(p.ymax, q.ymax), std::min(p.zmax, q.zmax)};
        return {std::min(p.xmin, q.xmin), std::min(p.ymin, q.ymin), std::min(p.zmin, q.zmin),
                std::max(p.xmax, q.xmax), std::max(p.ymax, q.ymax), std::max(p.zmax, q.zmax)};
    }
    double feature_size() const override {
        const double fa = a_->feature_size(), fb = b_->feature_size();
        return op_ == Op::union_ ? std::min(fa, fb) : fa > 0 && fb > 0 ? std::min(fa, fb) : 0.0;
    }
    std::string describe() const override {
        const char* name = op_ == Op::union_ ? "union(" : op_ == Op::intersection ? "intersect(" : "diff(";
        return name + a_->describe() + ";" + b_->describe() + ")";
    }

private:
    Op op_;
    std::unique_ptr<LevelSet3> a_, b_;
};

bool disjoint(const Box3& p, const Box3& q) {
    return p.xmax < q.xmin || q.xmax < p.xmin || p.ymax < q.ymin || q.ymax < p.ymin || p.zmax < q.zmin ||
           q.zmax < p.zmin;
}

std::unique_ptr<LevelSet3> parse(std::string_view s);

std::unique_ptr<LevelSet3> primitive(std::string_view name, std::string_view args) {
    struct Kind {
        std::string_view name, params;
        std::size_t arity;
    };
    static constexpr Kind kinds[] = {{"sphere", "cx,cy,cz,r", 4},
                                     {"ellipsoid", "cx,cy,cz,a,b,c", 6},
                                     {"torus", "cx,cy,cz,R,r", 5},
                                     {"box", "x0,y0,z0,x1,y1,z1", 6},
                                     {"cylinder", "x0,y0,z0,x1,y1,z1,r", 7}};
    const Kind* kind = nullptr;
    for (const Kind& k : kinds)
        if (k.name == name) kind = &k;
    require(kind != nullptr, "unknown shape '" + std::string(name) +
                                 "' (expected sphere, ellipsoid, torus, box, cylinder, union, intersect or diff)");
    const std::vector<double> v = shape_syntax::parse_numbers(args, name);
    require(v.size() == kind->arity, std::string(name) + " takes " + std::to_string(kind->arity) + " numbers (" +
                                         std::string(kind->params) + "), got " + std::to_string(v.size()));
    if (name == "sphere") return std::make_unique<Sphere>(v[0], v[1], v[2], v[3]);
    if (name == "ellipsoid") return std::make_unique<Ellipsoid>(v[0], v[1], v[2], v[3], v[4], v[5]);
    if (name == "torus") return std::make_unique<Torus>(v[0], v[1], v[2], v[3], v[4]);
    if (name == "box") return std::make_unique<BoxShape>(Box3{v[0], v[1], v[2], v[3], v[4], v[5]});
    return std::make_unique<Cylinder>(Point3{v[0], v[1], v[2]}, Point3{v[3], v[4], v[5]}, v[6]);
}

std::unique_ptr<LevelSet3> csg(Op op, std::string_view name, std::string_view inner) {
    const std::vector<std::string_view> parts = shape_syntax::split_parts(inner, name);
    std::unique_ptr<LevelSet3> acc = parse(parts[0]);
    for (std::size_t i = 1; i < parts.size(); ++i) {
        std::unique_ptr<LevelSet3> next = parse(parts[i]);
        require(op != Op::intersection || !disjoint(acc->bounds(), next->bounds()),
                "the region is empty (intersect(" + acc->describe() + ";" + next->describe() +
                    ") is empty: their bounding boxes are disjoint); nothing to mesh");
        acc = std::make_unique<Csg3>(op, std::move(acc), std::move(next));
    }
    return acc;
}

std::unique_ptr<LevelSet3> parse(std::string_view s) {
    const shape_syntax::Term t = shape_syntax::split_term(s, "sphere:0,0,0,1");
    if (!t.operation) return primitive(t.name, t.body);
    if (t.name == "union") return csg(Op::union_, t.name, t.body);
    if (t.name == "intersect" || t.name == "intersection") return csg(Op::intersection, t.name, t.body);
    if (t.name == "diff" || t.name == "difference") return csg(Op::difference, t.name, t.body);
    throw InputError("unknown operation '" + std::string(t.name) + "' (expected union, intersect or diff)");
}

}  // namespace

std::unique_ptr<LevelSet3> parse_shape3(const std::string& spec) {
    try {
        return parse(spec);
    } catch (const InputError& e) {
        throw InputError("shape '" + spec + "': " + e.what());
    }
}

}  // namespace warpmesh
