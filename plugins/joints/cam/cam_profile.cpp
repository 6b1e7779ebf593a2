#include "cam_profile.hpp"

#include <mbd/sdk/text.hpp>

#include <cmath>
#include <stdexcept>

namespace mbd::cam {

ProfilePoint Profile::point(double phi) const {
    const RadiusValue r = radius(phi);
    const Vec2 e_r(std::cos(phi), std::sin(phi)), e_phi(-std::sin(phi), std::cos(phi));
    return {r.d * e_r, r.d1 * e_r + r.d * e_phi, (r.d2 - r.d) * e_r + 2.0 * r.d1 * e_phi};
}

namespace {

class Eccentric final : public Profile {
public:
    Eccentric(double R, double e) : R_(R), e_(e) {}
    RadiusValue radius(double phi) const override {
        const double s = std::sin(phi), c = std::cos(phi);
        const double w = std::sqrt(R_ * R_ - e_ * e_ * s * s);
        const double e2 = e_ * e_;
        return {e_ * c + w, -e_ * s - e2 * s * c / w,
                -e_ * c - e2 * std::cos(2.0 * phi) / w - e2 * e2 * s * s * c * c / (w * w * w)};
    }

private:
    double R_, e_;
};

class Harmonic final : public Profile {
public:
    Harmonic(double a0, std::vector<double> a, std::vector<double> b) : a0_(a0), a_(std::move(a)), b_(std::move(b)) {}
    RadiusValue radius(double phi) const override {
        RadiusValue r{a0_, 0.0, 0.0};
        const size_t n = std::max(a_.size(), b_.size());
        for (size_t k = 1; k <= n; ++k) {
            const double ak = k <= a_.size() ? a_[k - 1] : 0.0, bk = k <= b_.size() ? b_[k - 1] : 0.0;
            const double kk = static_cast<double>(k), c = std::cos(kk * phi), s = std::sin(kk * phi);
            r.d += ak * c + bk * s;
            r.d1 += kk * (-ak * s + bk * c);
            r.d2 -= kk * kk * (ak * c + bk * s);
        }
        return r;
    }

private:
    double a0_;
    std::vector<double> a_, b_;
};

// Periodic cubic spline: on [phi_k, phi_k+1] with h = 2 pi / n and t = (phi - phi_k) / h,
//   d = (1 - t) d_k + t d_k+1 + h^2 / 6 [((1 - t)^3 - (1 - t)) M_k + (t^3 - t) M_k+1],
// where the nodal second derivatives M satisfy (C1 at every node, indices mod n)
//   M_k-1 + 4 M_k + M_k+1 = 6 (d_k+1 - 2 d_k + d_k-1) / h^2.
class PeriodicSpline final : public Profile {
public:
    explicit PeriodicSpline(std::vector<double> radii) : d_(std::move(radii)) {
        const int n = static_cast<int>(d_.size());
        h_ = 2.0 * M_PI / n;
        M_.assign(n, 0.0);
        // The cyclic system is strictly diagonally dominant: Gauss-Seidel converges fast
        // (spectral radius 1/2), and n is small (tens of nodes).
        std::vector<double> rhs(n);
        for (int k = 0; k < n; ++k) rhs[k] = 6.0 * (d_[(k + 1) % n] - 2.0 * d_[k] + d_[(k + n - 1) % n]) / (h_ * h_);
        for (int sweep = 0; sweep < 200; ++sweep) {
            double change = 0.0, scale = 0.0;
            for (int k = 0; k < n; ++k) {
                const double m = (rhs[k] - M_[(k + n - 1) % n] - M_[(k + 1) % n]) / 4.0;
                change = std::max(change, std::abs(m - M_[k]));
                scale = std::max(scale, std::abs(m));
                M_[k] = m;
            }
            if (change <= 1e-16 * std::max(scale, 1e-300)) break;
        }
    }
    RadiusValue radius(double phi) const override {
        const int n = static_cast<int>(d_.size());
        const double x = phi / h_;
        const double cell = std::floor(x);
        const double t = x - cell;
        int k = static_cast<int>(std::fmod(cell, static_cast<double>(n)));
        if (k < 0) k += n;
        const int k1 = (k + 1) % n;
        const double u = 1.0 - t, h2 = h_ * h_;
        RadiusValue r;
        r.d = u * d_[k] + t * d_[k1] + h2 / 6.0 * ((u * u * u - u) * M_[k] + (t * t * t - t) * M_[k1]);
        r.d1 = (d_[k1] - d_[k]) / h_ + h_ / 6.0 * (-(3.0 * u * u - 1.0) * M_[k] + (3.0 * t * t - 1.0) * M_[k1]);
        r.d2 = u * M_[k] + t * M_[k1];
        return r;
    }

private:
    std::vector<double> d_, M_;
    double h_ = 1.0;
};

std::vector<double> numbers(const Params& p, const std::string& key) {
    const Eigen::VectorXd v = p.vector(key);
    return std::vector<double>(v.data(), v.data() + v.size());
}

// The keys of each profile type (the `profile:` map p, its type already read).
std::unique_ptr<const Profile> read_eccentric(const Params& p) {
    const double R = p.positive("radius");
    const double e = p.non_negative("eccentricity", 0.0);
    if (!(e < R)) p.at("eccentricity").fail("'eccentricity' must be less than 'radius' (" + p.at("radius").text +
                                            "), so that the circle encloses the cam's centre");
    return std::make_unique<Eccentric>(R, e);
}

std::unique_ptr<const Profile> read_harmonic(const Params& p) {
    const double a0 = p.positive("base");
    std::vector<double> a = p.has("cos") ? numbers(p, "cos") : std::vector<double>{};
    std::vector<double> b = p.has("sin") ? numbers(p, "sin") : std::vector<double>{};
    double amplitude = 0.0;
    for (double x : a) amplitude += std::abs(x);
    for (double x : b) amplitude += std::abs(x);
    if (!(amplitude < a0))
        p.fail("the harmonic amplitudes (sum of |cos| and |sin| terms " + std::to_string(amplitude) +
               ") must be less than 'base' " + p.at("base").text + ", so that the radius stays positive");
    return std::make_unique<Harmonic>(a0, std::move(a), std::move(b));
}

std::unique_ptr<const Profile> read_spline(const Params& p) {
    std::vector<double> radii = numbers(p, "radii");
    if (radii.size() < 4) p.at("radii").fail("'radii' needs at least 4 radii (equally spaced in angle from 0)");
    for (double r : radii)
        if (!(r > 0.0)) p.at("radii").fail("every entry of 'radii' must be positive");
    return std::make_unique<PeriodicSpline>(std::move(radii));
}

// The signed curvature of the polar curve d(phi) (positive where it bends towards the origin):
//   kappa = (d^2 + 2 d'^2 - d d'') / (d^2 + d'^2)^(3/2).
double curvature(const RadiusValue& r) {
    return (r.d * r.d + 2.0 * r.d1 * r.d1 - r.d * r.d2) / std::pow(r.d * r.d + r.d1 * r.d1, 1.5);
}

// A convex profile curves towards its centre everywhere: the joint's contact search follows
// one point of contact, and a hollow would give the follower a second one (or none). Sampled
// densely (a spline of up to a few hundred radii has several samples per interval); the most
// hollow sample names where the profile fails.
void require_convex(const Profile& profile, const Params& p, const std::string& who) {
    constexpr int kSamples = 4096;
    double worst = HUGE_VAL, worst_phi = 0.0;
    for (int k = 0; k < kSamples; ++k) {
        const double phi = 2.0 * M_PI * k / kSamples, kappa = curvature(profile.radius(phi));
        if (kappa < worst) worst = kappa, worst_phi = phi;
    }
    if (!(worst > 0.0))
        p.fail(who + ": the profile is not convex: at phi = " + format_number(worst_phi) + " rad (radius " +
               format_number(profile.radius(worst_phi).d) + " m) it curves away from the centre (curvature " +
               format_number(worst) + " 1/m); the cam joint needs a convex profile (one point of contact): "
               "change the radii or amplitudes there");
}

}  // namespace

std::unique_ptr<const Profile> periodic_spline(const std::vector<double>& radii) {
    return std::make_unique<PeriodicSpline>(radii);
}

std::unique_ptr<const Profile> read_profile(const Params& params, const std::string& who) {
    const Params p = params.child("profile");
    const std::string type = p.string("type");
    std::unique_ptr<const Profile> profile;
    if (type == "eccentric") profile = read_eccentric(p);  // a circle: convex
    else if (type == "harmonic") profile = read_harmonic(p);
    else if (type == "spline") profile = read_spline(p);
    else p.at("type").fail(who + ": unknown profile type '" + type + "' (eccentric, harmonic or spline)");
    require_convex(*profile, p, who);
    return profile;
}

}  // namespace mbd::cam
