// Body type `ancf_cable`: a beam meshed between two points into N gradient-deficient ANCF
// elements. In planar scenes (this file, ancf_cable_element.hpp) the coordinates are, node by
// node, [r_k (x, y), r'_k (x, y)], 4 (N + 1) in all; in spatial scenes the spatial element
// (ancf_cable_3d.cpp). Velocities are their rates. The material parameter of a point is its arc
// length x in [0, L] from `from` in the straight reference configuration.
#include "ancf_cable_3d.hpp"
#include "ancf_cable_element.hpp"
#include "meshed_beam.hpp"

#include <mbd/sdk/body.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace mbd {
namespace {

using ancf::Mat8;
using ancf::Vec8;

using ancf::positive;

class AncfCable final : public ancf::MeshedBeamOf<AncfCable, 8, 4> {
public:
    explicit AncfCable(const BodySpec& spec) : MeshedBeamOf(ancf::read_beam_line(spec.params, 2), {2, 4, {0, 2, 4, 6}}) {
        const Params& p = spec.params;
        from_ = line_.from;
        tangent_ = line_.tangent;
        elements_ = line_.elements;
        const double E = positive(p, "modulus"), A = positive(p, "area"), I = positive(p, "second_moment");
        section_ = {E * A, E * I, positive(p, "density") * A};
        // 5 Gauss points integrate the axial energy exactly; 2 relieve the membrane locking of a
        // nearly inextensible beam in bending, at the price of an axial zero-energy mode where no
        // node's slope is held (docs/plugin-sdk.md "Bodies")
        section_.axial_points = ancf::read_axial_points(p);
        element_length_ = line_.element_length();
        assemble_mass(ancf::element_mass(section_, element_length_), 4);
    }

    int coordinates() const override { return 4 * (elements_ + 1); }
    Eigen::VectorXd initial_coordinates() const override {
        Eigen::VectorXd q(coordinates());
        for (int k = 0; k <= elements_; ++k) {
            q.segment<2>(4 * k) = from_ + (k * element_length_) * tangent_;
            q.segment<2>(4 * k + 2) = tangent_;
        }
        return q;
    }
    std::string coordinate_name(int k) const override {
        static const char* const part[4] = {"x", "y", "slope_x", "slope_y"};
        return "node" + std::to_string(k / 4) + "_" + part[k % 4];
    }

    void gravity_forces(const Eigen::VectorXd& /*q*/, const Vec3& g, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Q.setZero();
        for (int j = 0; j < elements_; ++j)
            Q.segment<8>(4 * j) += ancf::element_gravity(section_, element_length_, g.head<2>());
    }

    // one element's strain energy, with its gradient and Hessian when asked (MeshedBeamOf assembles them)
    double element_energy(const Vec8& qe, Vec8* gradient, Mat8* hessian) const {
        return ancf::element_strain_energy(section_, element_length_, qe, gradient, hessian);
    }

    void point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialPoint& out) const override {
        const Located at = locate(xi[0]);
        const ancf::Shape f = ancf::shape(at.xi, element_length_);
        out.r.setZero();
        out.rdot.setZero();
        out.jacobian.setZero(3, coordinates());
        for (int k = 0; k < 4; ++k) {
            const int c = 4 * at.element + 2 * k;
            out.r.head<2>() += f.s[k] * q.segment<2>(c);
            out.rdot.head<2>() += f.s[k] * v.segment<2>(c);
            out.jacobian(0, c) = out.jacobian(1, c + 1) = f.s[k];
        }
    }
    // The frame at a point: origin r, x axis along the slope r' (sdk body.hpp for G and a).
    void frame(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialFrame& out) const override {
        const Located at = locate(xi[0]);
        const ancf::Shape f = ancf::shape(at.xi, element_length_);
        Eigen::Vector2d r = Eigen::Vector2d::Zero(), rdot = r, a = r, adot = r;
        out.jacobian.setZero(3, coordinates());
        for (int k = 0; k < 4; ++k) {
            const int c = 4 * at.element + 2 * k;
            r += f.s[k] * q.segment<2>(c);
            rdot += f.s[k] * v.segment<2>(c);
            a += f.ds[k] * q.segment<2>(c);
            adot += f.ds[k] * v.segment<2>(c);
        }
        const double g = a.squaredNorm();
        const double cross = a.x() * adot.y() - a.y() * adot.x();
        for (int k = 0; k < 4; ++k) {
            const int c = 4 * at.element + 2 * k;
            out.jacobian(0, c) = out.jacobian(1, c + 1) = f.s[k];
            // theta = atan2(a_y, a_x): dtheta = (a x da) / |a|^2
            out.jacobian(2, c) = -f.ds[k] * a.y() / g;
            out.jacobian(2, c + 1) = f.ds[k] * a.x() / g;
        }
        out.planar.set(r, std::atan2(a.y(), a.x()), rdot, cross / g);
        // thetaddot = (a x addot) / g - 2 (a x adot)(a . adot) / g^2, and addot = S' vdot
        out.bias = Eigen::Vector3d(0.0, 0.0, -2.0 * cross * a.dot(adot) / (g * g));
    }

private:
    Eigen::Vector2d from_ = Eigen::Vector2d::Zero(), tangent_ = Eigen::Vector2d::UnitX();
    double element_length_ = 0.0;
    int elements_ = 0;
    ancf::Section section_;
};

std::unique_ptr<FlexibleBody> make_ancf_cable(const BodySpec& spec) {
    if (spec.dimension == Dimension::Spatial) return ancf::make_spatial_cable(spec);
    return std::make_unique<AncfCable>(spec);
}

}  // namespace
}  // namespace mbd

MBD_BODY_PLUGIN(ancf_cable, mbd::make_ancf_cable)
