// Body type `ancf_beam`: a planar shear-deformable beam meshed between two points into N fully
// parameterized ANCF elements (ancf_beam_element.hpp). Coordinates, node by node:
// [r_k (x, y), r_k_x (x, y), r_k_y (x, y)], 6 (N + 1) in all; velocities are their rates. The
// material parameter of a point is its arc length x in [0, L] from `from` along the reference
// centre line; the point is on the centre line, and its frame is the cross-section's: x axis
// e1 (the director d = r_y turned by -90 degrees), angle atan2(-d_x, d_y), so that a clamp holds
// the section (not the centre line's slope, which differs from it by the shear angle).
#include "ancf_beam_element.hpp"
#include "meshed_beam.hpp"

#include <mbd/sdk/body.hpp>

#include <cmath>
#include <string>

namespace mbd {
namespace {

using ancf::positive;
using ancf::shear::kCentre;
using ancf::shear::kDirector;
using ancf::shear::Mat12;
using ancf::shear::Vec12;

class AncfBeam final : public ancf::MeshedBeamOf<AncfBeam, 12, 6> {
public:
    explicit AncfBeam(const BodySpec& spec) : MeshedBeamOf(read_line(spec), {2, 6, {kCentre[0], kCentre[1], kCentre[2], kCentre[3]}}) {
        const Params& p = spec.params;
        const double E = positive(p, "modulus"), G = positive(p, "shear_modulus");
        const double A = positive(p, "area"), I = positive(p, "second_moment"), rho = positive(p, "density");
        // 5/6: the rectangular section's shear correction factor (Timoshenko; Cowper 1966 gives
        // 10 (1 + nu) / (12 + 11 nu) for a given Poisson ratio)
        const double k = p.has("shear_factor") ? positive(p, "shear_factor") : 5.0 / 6.0;
        section_ = {E * A, k * G * A, E * I, rho * A, rho * I};
        l_ = line_.element_length();
        assemble_mass(ancf::shear::element_mass(section_, l_), 6);
    }

    int coordinates() const override { return 6 * (line_.elements + 1); }
    Eigen::VectorXd initial_coordinates() const override {
        const Eigen::Vector2d t = line_.tangent, across(-t.y(), t.x());
        Eigen::VectorXd q(coordinates());
        for (int k = 0; k <= line_.elements; ++k) {
            q.segment<2>(6 * k) = line_.from + (k * l_) * t;
            q.segment<2>(6 * k + 2) = t;
            q.segment<2>(6 * k + 4) = across;
        }
        return q;
    }
    std::string coordinate_name(int k) const override {
        static const char* const part[6] = {"x", "y", "slope_x", "slope_y", "director_x", "director_y"};
        return "node" + std::to_string(k / 6) + "_" + part[k % 6];
    }

    void gravity_forces(const Eigen::VectorXd& /*q*/, const Vec3& g, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Q.setZero();
        const Vec12 Qe = ancf::shear::element_gravity(section_, l_, g.head<2>());
        for (int j = 0; j < line_.elements; ++j) Q.segment<12>(6 * j) += Qe;
    }

    // one element's strain energy, with its gradient and Hessian when asked (MeshedBeamOf assembles them)
    double element_energy(const Vec12& qe, Vec12* gradient, Mat12* hessian) const {
        return ancf::shear::element_strain_energy(section_, l_, qe, gradient, hessian);
    }

    void point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialPoint& out) const override {
        const Located at = locate(xi[0]);
        const beam::Shape f = beam::shape(at.xi, l_);
        out.r.setZero();
        out.rdot.setZero();
        out.jacobian.setZero(3, coordinates());
        for (int k = 0; k < 4; ++k) {
            const int c = 6 * at.element + kCentre[k];
            out.r.head<2>() += f.s[k] * q.segment<2>(c);
            out.rdot.head<2>() += f.s[k] * v.segment<2>(c);
            out.jacobian(0, c) = out.jacobian(1, c + 1) = f.s[k];
        }
    }
    // The cross-section's frame (top of this file): theta = atan2(-d_x, d_y) turns at
    // (d x ddot) / |d|^2, whose rate at ddot fixed is -2 (d x ddot)(d . ddot) / |d|^4 (d is linear in q).
    void frame(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialFrame& out) const override {
        MaterialPoint centre;
        point(q, v, xi, centre);
        const Located at = locate(xi[0]);
        const double weight[2] = {1.0 - at.xi, at.xi};
        Eigen::Vector2d d = Eigen::Vector2d::Zero(), ddot = d;
        for (int k = 0; k < 2; ++k) {
            d += weight[k] * q.segment<2>(6 * at.element + kDirector[k]);
            ddot += weight[k] * v.segment<2>(6 * at.element + kDirector[k]);
        }
        const double g = d.squaredNorm(), cross = d.x() * ddot.y() - d.y() * ddot.x();
        out.jacobian.setZero(3, coordinates());
        out.jacobian.topRows<2>() = centre.jacobian.topRows<2>();
        for (int k = 0; k < 2; ++k) {
            const int c = 6 * at.element + kDirector[k];
            out.jacobian(2, c) = -weight[k] * d.y() / g;
            out.jacobian(2, c + 1) = weight[k] * d.x() / g;
        }
        out.planar.set(centre.r.head<2>(), std::atan2(-d.x(), d.y()), centre.rdot.head<2>(), cross / g);
        out.bias = Eigen::Vector3d(0.0, 0.0, -2.0 * cross * d.dot(ddot) / (g * g));
    }

private:
    static ancf::BeamLine read_line(const BodySpec& spec) {
        if (spec.dimension != Dimension::Planar)
            spec.params.fail("the ancf_beam (shear-deformable) body is planar; in a spatial scene use ancf_cable");
        return ancf::read_beam_line(spec.params, 2);
    }

    ancf::shear::Section section_;
    double l_ = 0.0;
};

std::unique_ptr<FlexibleBody> make_ancf_beam(const BodySpec& spec) { return std::make_unique<AncfBeam>(spec); }

}  // namespace
}  // namespace mbd

MBD_BODY_PLUGIN(ancf_beam, mbd::make_ancf_beam)
