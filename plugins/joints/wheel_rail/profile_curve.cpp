#include "profile_curve.hpp"

#include <algorithm>
#include <cmath>

namespace mbd::wheel_rail {
namespace {

// A straight profile; `half_width` bounds it (a cone's tread), infinite for a flat head.
class Line final : public ProfileCurve {
public:
    Line(double f0, double slope, double half_width = HUGE_VAL) : f0_(f0), slope_(slope), half_width_(half_width) {}
    CurveValue at(double x) const override { return {f0_ + slope_ * x, slope_, 0.0}; }
    bool straight() const override { return true; }
    Range domain() const override { return {-half_width_, half_width_}; }

private:
    double f0_, slope_, half_width_;
};

// h = sqrt(R^2 - y^2) - R; beyond |y| = R the head has ended (the search is kept inside).
class Arc final : public ProfileCurve {
public:
    explicit Arc(double R) : R_(R) {}
    CurveValue at(double y) const override {
        const double w2 = R_ * R_ - y * y, w = std::sqrt(w2);
        return {w - R_, -y / w, -R_ * R_ / (w2 * w)};
    }
    double clamp(double y) const override { return std::clamp(y, -0.9 * R_, 0.9 * R_); }
    double where_slope(double slope, double) const override { return -R_ * slope / std::sqrt(1.0 + slope * slope); }
    Range domain() const override { return {-R_, R_}; }

private:
    double R_;
};

// On [x_k, x_k+1] with h = x_k+1 - x_k, t = (x - x_k) / h, u = 1 - t:
//   f = u f_k + t f_k+1 + h^2 / 6 [(u^3 - u) M_k + (t^3 - t) M_k+1],
// the nodal second derivatives M from C1 at the inner nodes and M = 0 at both ends:
//   h_k-1 M_k-1 + 2 (h_k-1 + h_k) M_k + h_k M_k+1 = 6 [(f_k+1 - f_k) / h_k - (f_k - f_k-1) / h_k-1].
class NaturalSpline final : public ProfileCurve {
public:
    NaturalSpline(std::vector<double> x, std::vector<double> f) : x_(std::move(x)), f_(std::move(f)) {
        const size_t n = x_.size();
        M_.assign(n, 0.0);
        if (n < 3) return;
        // Thomas algorithm on the inner nodes 1 .. n-2 (diagonally dominant: no pivoting).
        std::vector<double> diag(n, 0.0), rhs(n, 0.0);
        for (size_t k = 1; k + 1 < n; ++k) {
            const double h0 = x_[k] - x_[k - 1], h1 = x_[k + 1] - x_[k];
            diag[k] = 2.0 * (h0 + h1);
            rhs[k] = 6.0 * ((f_[k + 1] - f_[k]) / h1 - (f_[k] - f_[k - 1]) / h0);
        }
        for (size_t k = 2; k + 1 < n; ++k) {
            const double lower = x_[k] - x_[k - 1], factor = lower / diag[k - 1];
            diag[k] -= factor * lower;
            rhs[k] -= factor * rhs[k - 1];
        }
        for (size_t k = n - 2; k >= 1; --k) {
            M_[k] = (rhs[k] - (x_[k + 1] - x_[k]) * M_[k + 1]) / diag[k];
            if (k == 1) break;
        }
    }
    CurveValue at(double x) const override {
        const size_t n = x_.size();
        if (x <= x_.front()) return straight_end(0, x);
        if (x >= x_.back()) return straight_end(n - 2, x, true);
        const size_t k = static_cast<size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
        return inside(k, x);
    }
    double clamp(double x) const override { return std::clamp(x, x_.front(), x_.back()); }
    Range domain() const override { return {x_.front(), x_.back()}; }
    // f' is piecewise quadratic: the first knot interval where f' - slope changes sign, then
    // bisection there (a convex or concave profile has at most one such interval)
    double where_slope(double slope, double guess) const override {
        for (size_t k = 0; k + 1 < x_.size(); ++k) {
            double lo = x_[k], hi = x_[k + 1];
            double f_lo = inside(k, lo).f1 - slope;
            const double f_hi = inside(k, hi).f1 - slope;
            if (f_lo == 0.0) return lo;
            if ((f_lo < 0.0) == (f_hi < 0.0)) continue;
            for (int halving = 0; halving < 60; ++halving) {
                const double mid = 0.5 * (lo + hi), f_mid = inside(k, mid).f1 - slope;
                if ((f_mid < 0.0) == (f_lo < 0.0)) {
                    lo = mid;
                    f_lo = f_mid;
                } else {
                    hi = mid;
                }
            }
            return 0.5 * (lo + hi);
        }
        return clamp(guess);
    }

private:
    CurveValue inside(size_t k, double x) const {
        const double h = x_[k + 1] - x_[k], t = (x - x_[k]) / h, u = 1.0 - t;
        CurveValue c;
        c.f = u * f_[k] + t * f_[k + 1] + h * h / 6.0 * ((u * u * u - u) * M_[k] + (t * t * t - t) * M_[k + 1]);
        c.f1 = (f_[k + 1] - f_[k]) / h + h / 6.0 * (-(3.0 * u * u - 1.0) * M_[k] + (3.0 * t * t - 1.0) * M_[k + 1]);
        c.f2 = u * M_[k] + t * M_[k + 1];
        return c;
    }
    // beyond an end point: the tangent line there (M = 0 at the ends, so still C2)
    CurveValue straight_end(size_t k, double x, bool right = false) const {
        const double x_end = right ? x_[k + 1] : x_[k];
        const CurveValue end = inside(k, x_end);
        return {end.f + end.f1 * (x - x_end), end.f1, 0.0};
    }

    std::vector<double> x_, f_, M_;
};

// `points: [[x, f], ...]`, x strictly increasing, at least 3 points.
std::unique_ptr<const ProfileCurve> read_spline(const Params& p, const std::string& who, const std::string& section) {
    const Param& node = p.at("points");
    const std::string what = who + ": '" + section + ".points'";
    if (!node.is_list() || node.items.size() < 3)
        node.fail(what + " must be a list of at least 3 points [lateral, value]");
    std::vector<double> x, f;
    for (const Param& item : node.items) {
        const Eigen::VectorXd point = item.as_vector("points", 2, who);
        if (!x.empty() && !(point[0] > x.back()))
            item.fail(what + ": the lateral coordinates must be strictly increasing (" + std::to_string(point[0]) +
                      " follows " + std::to_string(x.back()) + ")");
        x.push_back(point[0]);
        f.push_back(point[1]);
    }
    return std::make_unique<NaturalSpline>(std::move(x), std::move(f));
}

}  // namespace

std::unique_ptr<const ProfileCurve> read_wheel_profile(const Params& joint, const std::string& who) {
    const Params p = joint.child("wheel");
    const std::string type = p.string("type");
    if (type == "cone") {
        const double r0 = p.positive("radius");
        const double gamma = p.number("cone_angle", 0.0);
        if (!(std::abs(gamma) < 0.5 * M_PI))
            p.at("cone_angle").fail(who + ": 'wheel.cone_angle' must lie between -pi/2 and pi/2 (rad)");
        // the tread spans s in [-width/2, width/2]; by default as wide as the wheel is high
        const double width = p.has("width") ? p.positive("width") : 2.0 * r0;
        return std::make_unique<Line>(r0, -std::tan(gamma), 0.5 * width);
    }
    if (type == "spline") {
        auto spline = read_spline(p, who, "wheel");
        for (const Param& item : p.at("points").items)
            if (!(item.items[1].as_number("points", who) > 0.0))
                item.fail(who + ": every radius of 'wheel.points' must be positive");
        return spline;
    }
    p.at("type").fail(who + ": unknown wheel profile type '" + type + "' (cone or spline)");
}

std::unique_ptr<const ProfileCurve> read_rail_profile(const Params& joint, const std::string& who) {
    const Params p = joint.child("rail");
    const std::string type = p.string("type");
    if (type == "flat") return std::make_unique<Line>(0.0, 0.0);
    if (type == "arc") return std::make_unique<Arc>(p.positive("radius"));
    if (type == "spline") return read_spline(p, who, "rail");
    p.at("type").fail(who + ": unknown rail profile type '" + type + "' (flat, arc or spline)");
}

}  // namespace mbd::wheel_rail
