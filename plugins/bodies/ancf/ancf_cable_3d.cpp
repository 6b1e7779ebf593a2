// The spatial `ancf_cable`: a beam meshed between two points into N spatial gradient-deficient
// ANCF elements (ancf_cable_3d_element.hpp). Coordinates, node by node: [r_k (x, y, z),
// r'_k (x, y, z)], 6 (N + 1) in all; velocities are their rates. The material parameter of a
// point is its arc length x in [0, L] from `from` in the straight reference configuration.
//
// Material frame at x: origin r(x), x axis the tangent t = r'/|r'|. The element has no twist
// coordinate, so its rotation about the tangent is fixed by a reference direction n (the key
// `normal`, world axes; default z, or x for a beam closer to z than 45 degrees): the frame's z axis
// is n's part across the tangent, z = (n - (n.t) t) / |n - (n.t) t|, and y = z x t. A frame is
// defined while the tangent is not parallel to n. In a plane normal to n this is the planar
// cable's frame (angle atan2(r'_y, r'_x) about n = z).
#include "ancf_cable_3d.hpp"

#include "ancf_cable_3d_element.hpp"
#include "meshed_beam.hpp"

#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace mbd::ancf {
namespace {

using spatial::Mat12;
using spatial::Vec12;

// The frame's axes at a tangent a = r' and their angular velocity wbar (frame axes) for a rate
// adot. With t = a / rho: tdot = (I - t t^T) adot / rho, so wbar_z = y . adot / rho and
// wbar_y = -z . adot / rho; z follows n across t, so wbar_x = -y . zdot = c wbar_z with
// c = (n . t) / |n - (n . t) t|. Hence wbar = B adot with rows (c y, -z, y) / rho.
struct TangentFrame {
    Eigen::Vector3d t, y, z;
    double rho = 0.0, s = 0.0, c = 0.0;  // |a|, n . t, (n . t) / sqrt(1 - (n . t)^2)
    TangentFrame(const Eigen::Vector3d& a, const Eigen::Vector3d& n) {
        rho = a.norm();
        t = a / rho;
        s = n.dot(t);
        const Eigen::Vector3d u = n - s * t;
        const double across = u.norm();
        if (!(across > 1e-8))
            throw DomainError("the cable's tangent is parallel to its reference direction 'normal' " +
                              format_number(n.x()) + ", " + format_number(n.y()) + ", " + format_number(n.z()) +
                              ": the frame's rotation about the tangent is undefined there; choose a 'normal' "
                              "across the beam's motion");
        z = u / across;
        y = z.cross(t);
        c = s / across;
    }
    Eigen::Vector3d angular_velocity(const Eigen::Vector3d& adot) const {
        const double wz = y.dot(adot) / rho;
        return Eigen::Vector3d(c * wz, -z.dot(adot) / rho, wz);
    }
    // d/dt (B) adot at a fixed adot: the frame's angular acceleration when addot = 0.
    Eigen::Vector3d bias(const Eigen::Vector3d& adot, const Eigen::Vector3d& n) const {
        const Eigen::Vector3d w = angular_velocity(adot);
        const Eigen::Vector3d tdot = w.z() * y - w.y() * z;
        const Eigen::Vector3d ydot = -w.z() * t + w.x() * z, zdot = -w.x() * y + w.y() * t;
        const double rhodot = t.dot(adot);
        const double by = -zdot.dot(adot) / rho + z.dot(adot) * rhodot / (rho * rho);
        const double bz = ydot.dot(adot) / rho - y.dot(adot) * rhodot / (rho * rho);
        const double cdot = n.dot(tdot) / std::pow(1.0 - s * s, 1.5);
        return Eigen::Vector3d(cdot * w.z() + c * bz, by, bz);
    }
    Mat3 axes() const {
        Mat3 A;
        A << t, y, z;
        return A;
    }
};

class SpatialCable final : public MeshedBeamOf<SpatialCable, 12, 6> {
public:
    explicit SpatialCable(const BodySpec& spec) : MeshedBeamOf(read_beam_line(spec.params, 3), {3, 6, {0, 3, 6, 9}}) {
        const Params& p = spec.params;
        from_ = line_.from;
        tangent_ = line_.tangent;
        elements_ = line_.elements;
        element_length_ = line_.element_length();
        const double E = positive(p, "modulus"), A = positive(p, "area"), I = positive(p, "second_moment");
        section_ = {E * A, E * I, positive(p, "density") * A, read_axial_points(p)};
        read_normal(p);
        assemble_mass(spatial::element_mass(section_, element_length_), 6);
    }

    int coordinates() const override { return 6 * (elements_ + 1); }
    Eigen::VectorXd initial_coordinates() const override {
        Eigen::VectorXd q(coordinates());
        for (int k = 0; k <= elements_; ++k) {
            q.segment<3>(6 * k) = from_ + (k * element_length_) * tangent_;
            q.segment<3>(6 * k + 3) = tangent_;
        }
        return q;
    }
    std::string coordinate_name(int k) const override {
        static const char* const part[6] = {"x", "y", "z", "slope_x", "slope_y", "slope_z"};
        return "node" + std::to_string(k / 6) + "_" + part[k % 6];
    }

    void gravity_forces(const Eigen::VectorXd& /*q*/, const Vec3& g, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Q.setZero();
        for (int j = 0; j < elements_; ++j) Q.segment<12>(6 * j) += spatial::element_gravity(section_, element_length_, g);
    }

    // one element's strain energy, with its gradient and Hessian when asked (MeshedBeamOf assembles them)
    double element_energy(const Vec12& qe, Vec12* gradient, Mat12* hessian) const {
        return spatial::element_strain_energy(section_, element_length_, qe, gradient, hessian);
    }

    void point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialPoint& out) const override {
        const Located at = locate(xi[0]);
        const beam::Shape f = beam::shape(at.xi, element_length_);
        out.r.setZero();
        out.rdot.setZero();
        out.jacobian.setZero(3, coordinates());
        for (int k = 0; k < 4; ++k) {
            const int col = 6 * at.element + 3 * k;
            out.r += f.s[k] * q.segment<3>(col);
            out.rdot += f.s[k] * v.segment<3>(col);
            out.jacobian.block<3, 3>(0, col).diagonal().setConstant(f.s[k]);
        }
    }
    // The frame at a point (top of this file; sdk body.hpp for G = [S; B S'] and a = [0; Bdot S' v]).
    void frame(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialFrame& out) const override {
        const Located at = locate(xi[0]);
        const beam::Shape f = beam::shape(at.xi, element_length_);
        Eigen::Vector3d r = Eigen::Vector3d::Zero(), rdot = r, a = r, adot = r;
        for (int k = 0; k < 4; ++k) {
            const int col = 6 * at.element + 3 * k;
            r += f.s[k] * q.segment<3>(col);
            rdot += f.s[k] * v.segment<3>(col);
            a += f.ds[k] * q.segment<3>(col);
            adot += f.ds[k] * v.segment<3>(col);
        }
        const TangentFrame tf(a, normal_);
        Eigen::Matrix3d B;  // wbar = B adot
        B << tf.c * tf.y.transpose(), -tf.z.transpose(), tf.y.transpose();
        B /= tf.rho;
        out.jacobian.setZero(6, coordinates());
        for (int k = 0; k < 4; ++k) {
            const int col = 6 * at.element + 3 * k;
            out.jacobian.block<3, 3>(0, col).diagonal().setConstant(f.s[k]);
            out.jacobian.block<3, 3>(3, col) = f.ds[k] * B;
        }
        const Mat3 A = tf.axes();
        out.spatial.set(r, euler_parameters_from_rotation(A), rdot, tf.angular_velocity(adot));
        out.spatial.A = A;  // exactly the axes (the Euler parameters round-trip to 1e-16)
        out.bias.setZero(6);
        out.bias.tail<3>() = tf.bias(adot, normal_);
    }

private:
    void read_normal(const Params& p) {
        if (!p.has("normal")) {
            normal_ = std::abs(tangent_.z()) < std::sqrt(0.5) ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
            return;
        }
        const Eigen::Vector3d n = p.vector("normal", 3);
        if (!(n.norm() > 0)) refuse(p, "normal", "'normal' must be a non-zero direction");
        normal_ = n.normalized();
        if (normal_.cross(tangent_).norm() < 1e-3)
            refuse(p, "normal", "'normal' is along the beam; the frame's reference direction must lie across it");
    }

    Eigen::Vector3d from_ = Eigen::Vector3d::Zero(), tangent_ = Eigen::Vector3d::UnitX();
    Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
    double element_length_ = 0.0;
    int elements_ = 0;
    spatial::Section section_;
};

}  // namespace

std::unique_ptr<FlexibleBody> make_spatial_cable(const BodySpec& spec) { return std::make_unique<SpatialCable>(spec); }

}  // namespace mbd::ancf
