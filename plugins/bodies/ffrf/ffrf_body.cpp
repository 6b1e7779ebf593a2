// Body type `ffrf_body`: a planar floating frame of reference plus modal coordinates (Shabana,
// Dynamics of Multibody Systems, Ch. 5 "Floating frame of reference formulation"). Coordinates
// q = [R (x, y), theta, p (m modal coordinates)], velocities their rates. The modes come from a
// cantilever beam mesh (beam_modes.hpp) or a mode file (mode_file.hpp); the inertia shape integrals
// they give are in modal_model.hpp, and every term below is written with them.
//
// A material point u = u0 + S p (body axes) has r = R + A u and
//     rdot = Rdot + thetadot A P u + A S pdot,   L = dr/dv = [I, A P u, A S],
//     rddot = L vdot + A (-thetadot^2 u + 2 thetadot P S pdot),
// so that the virtual work of the inertia forces, int rho dr^T rddot, gives M = int rho L^T L and
// Q_v = -int rho L^T A (-thetadot^2 u + 2 thetadot P S pdot) (the chapter's quadratic velocity
// vector; body.hpp's Q_v):
//     M_RR = m I       M_Rtheta = A P (S0 + Sbar p)     M_Rf = A Sbar
//     M_thetatheta = I00 + 2 I0f p + p^T Mff p          M_thetaf = I0Pf - p^T Stil     M_ff = Mff
//     Q_R = A (thetadot^2 (S0 + Sbar p) - 2 thetadot P Sbar pdot)
//     Q_theta = -2 thetadot (I0f + p^T Mff) pdot
//     Q_f = thetadot^2 (I0f^T + Mff p) - 2 thetadot Stil pdot.
// Geometric stiffening (`geometric_stiffening: true`, beam modes only): the foreshortening of a
// beam bent by w, u_x = -1/2 int_0^x w'^2, adds to the kinetic energy of a beam spinning about its
// root -1/2 thetadot^2 p^T Kg p to second order in p (Kane, Ryan and Banerjee, "Dynamics of a
// cantilever beam attached to a moving base", J. Guidance 10 (1987) 139-151; Kg in
// modal_model.hpp). So M_thetatheta gains -p^T Kg p, Q_theta gains 2 thetadot p^T Kg pdot and Q_f
// gains -thetadot^2 Kg p: the centrifugal axial force stiffens the bending modes. Without it a
// beam spun faster than its first bending frequency diverges (the linear model's known failure).
#include "beam_modes.hpp"
#include "mode_file.hpp"

#include <mbd/sdk/body.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <filesystem>
#include <string>

namespace mbd {
namespace {

using ffrf::ModalModel;
using ffrf::ModalPoint;

Eigen::Matrix2d rotation(double theta) { return Eigen::Rotation2Dd(theta).toRotationMatrix(); }
Eigen::Matrix2d generator() {  // P: dA/dtheta = A P
    Eigen::Matrix2d P;
    P << 0, -1, 1, 0;
    return P;
}

double positive(const Params& p, const std::string& key) {
    const double value = p.number(key);
    if (!(value > 0))
        throw InputError(p.at(key).location(), p.owner() + ": '" + key + "' must be positive, got " + p.at(key).text);
    return value;
}

bool flag(const Params& p, const std::string& key) {
    if (!p.has(key)) return false;
    const std::string text = p.string(key);
    if (text != "true" && text != "false")
        throw InputError(p.at(key).location(), p.owner() + ": '" + key + "' must be true or false, got " + text);
    return text == "true";
}

// The modes of the `mode_file` key, relative to the scene file's folder.
ModalModel modes_from_file(const Params& p) {
    std::filesystem::path path = p.string("mode_file");
    if (path.is_relative()) path = std::filesystem::path(p.at("mode_file").file).parent_path() / path;
    return ffrf::read_mode_file(path.string(), p.owner(), p.at("mode_file").location());
}

// The modes of a cantilever meshed between `from` and `to`; sets the frame's pose.
ModalModel modes_from_beam(const Params& p, Eigen::Vector2d& origin, double& angle) {
    origin = p.vector("from", 2);
    const Eigen::Vector2d to = p.vector("to", 2), axis = to - origin;
    const double length = axis.norm();
    if (!(length > 0))
        throw InputError(p.at("to").location(),
                         p.owner() + ": 'from' and 'to' coincide: the beam has zero length; give two distinct end points");
    angle = std::atan2(axis.y(), axis.x());
    const int elements = static_cast<int>(p.integer("elements", 0, 1000));
    if (elements < 1)
        throw InputError(p.at("elements").location(),
                         p.owner() + ": 'elements' must be at least 1: a beam element needs two nodes");
    const int modes = static_cast<int>(p.integer("modes", 1, 1000));
    if (modes > 2 * elements)
        throw InputError(p.at("modes").location(), p.owner() + ": " + std::to_string(modes) + " modes need at least " +
                                                       std::to_string((modes + 1) / 2) +
                                                       " elements (a clamped mesh of N elements has 2 N modes)");
    const double E = positive(p, "modulus"), A = positive(p, "area"), I = positive(p, "second_moment");
    return ffrf::cantilever_modes(length, elements, modes, {E * I, positive(p, "density") * A});
}

class FfrfBody final : public FlexibleBody {
public:
    explicit FfrfBody(const BodySpec& spec) : model_(0) {
        const Params& p = spec.params;
        if (spec.dimension != Dimension::Planar)
            p.fail("the ffrf_body is planar; a spatial FFRF body is not available yet");
        if (p.has("mode_file")) {
            model_ = modes_from_file(p);
            origin_ = p.has("position") ? Eigen::Vector2d(p.vector("position", 2)) : Eigen::Vector2d::Zero();
            angle_ = p.number("angle", 0.0);
        } else {
            model_ = modes_from_beam(p, origin_, angle_);
        }
        stiffening_ = flag(p, "geometric_stiffening");
        if (stiffening_ && model_.Kg.size() == 0)
            throw InputError(p.at("geometric_stiffening").location(),
                             p.owner() + ": geometric stiffening needs the beam's slopes: use the beam keys "
                                         "(from, to, elements, modes) instead of a mode file");
        m_ = model_.modes;
    }

    int coordinates() const override { return 3 + m_; }
    Eigen::VectorXd initial_coordinates() const override {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(coordinates());
        q.head<2>() = origin_;
        q[2] = angle_;
        return q;
    }
    std::string coordinate_name(int k) const override {
        static const char* const frame[3] = {"x", "y", "angle"};
        return k < 3 ? frame[k] : "mode" + std::to_string(k - 2);
    }

    void mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& M) const override {
        const auto p = q.tail(m_);
        const Eigen::Matrix2d A = rotation(q[2]);
        M.setZero(coordinates(), coordinates());
        M.topLeftCorner<2, 2>() = model_.mass * Eigen::Matrix2d::Identity();
        M.block<2, 1>(0, 2) = A * generator() * (model_.S0 + model_.Sbar * p);
        M.block(0, 3, 2, m_) = A * model_.Sbar;
        M(2, 2) = model_.I00 + 2.0 * model_.I0f.dot(p) + p.dot(model_.Mff * p) - (stiffening_ ? p.dot(model_.Kg * p) : 0.0);
        M.block(2, 3, 1, m_) = model_.I0Pf - p.transpose() * model_.Stilde;
        M.bottomRightCorner(m_, m_) = model_.Mff;
        M.triangularView<Eigen::StrictlyLower>() = M.transpose();
    }
    void quadratic_velocity_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                   Eigen::Ref<Eigen::VectorXd> Q) const override {
        const auto p = q.tail(m_), pdot = v.tail(m_);
        const double w = v[2];
        const Eigen::Matrix2d A = rotation(q[2]);
        Q.head<2>() = A * (w * w * (model_.S0 + model_.Sbar * p) - 2.0 * w * generator() * (model_.Sbar * pdot));
        Q[2] = -2.0 * w * (model_.I0f.dot(pdot) + p.dot(model_.Mff * pdot));
        Q.tail(m_) = w * w * (model_.I0f.transpose() + model_.Mff * p) - 2.0 * w * (model_.Stilde * pdot);
        if (stiffening_) {
            Q[2] += 2.0 * w * p.dot(model_.Kg * pdot);
            Q.tail(m_) -= w * w * (model_.Kg * p);
        }
    }
    void gravity_forces(const Eigen::VectorXd& q, const Vec3& g, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const Eigen::Vector2d g2 = g.head<2>();
        const Eigen::Matrix2d A = rotation(q[2]);
        Q.head<2>() = model_.mass * g2;
        Q[2] = g2.dot(A * generator() * (model_.S0 + model_.Sbar * q.tail(m_)));
        Q.tail(m_) = (A * model_.Sbar).transpose() * g2;
    }
    double gravity_potential(const Eigen::VectorXd& q, const Vec3& g) const override {
        const Eigen::Vector2d first_moment = model_.mass * q.head<2>() + rotation(q[2]) * (model_.S0 + model_.Sbar * q.tail(m_));
        return -g.head<2>().dot(first_moment);
    }

    double strain_energy(const Eigen::VectorXd& q) const override { return 0.5 * q.tail(m_).dot(model_.Kff * q.tail(m_)); }
    void elastic_forces(const Eigen::VectorXd& q, Eigen::Ref<Eigen::VectorXd> Q) const override {
        Q.setZero();
        Q.tail(m_) = -model_.Kff * q.tail(m_);
    }
    void elastic_jacobian(const Eigen::VectorXd& /*q*/, Eigen::Ref<Eigen::MatrixXd> dQ_dq) const override {
        dQ_dq.setZero();
        dQ_dq.bottomRightCorner(m_, m_) = -model_.Kff;
    }

    int material_parameters() const override { return 1; }
    void check_material_point(const double* xi) const override {
        const double slack = 1e-12 * (1.0 + model_.highest);
        if (!(xi[0] >= model_.lowest - slack && xi[0] <= model_.highest + slack))
            throw InputError("", "the point at " + model_.parameter + " " + format_number(xi[0]) +
                                     " lies outside the body [" + format_number(model_.lowest) + ", " +
                                     format_number(model_.highest) + "]");
        if (model_.whole_parameter && xi[0] != std::round(xi[0]))
            throw InputError("", "a mode file's material point is a node index, got " + format_number(xi[0]));
    }
    void point(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialPoint& out) const override {
        const Kinematics k = kinematics(q, v, xi[0]);
        out.r << k.r, 0.0;
        out.rdot << k.rdot, 0.0;
        out.jacobian.setZero(3, coordinates());
        out.jacobian.topRows(2) = k.L;
    }
    // The material frame: origin at the point, turned by the modes' small rotation (sdk body.hpp).
    void frame(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const double* xi, MaterialFrame& out) const override {
        const Kinematics k = kinematics(q, v, xi[0]);
        out.jacobian.setZero(3, coordinates());
        out.jacobian.topRows(2) = k.L;
        out.jacobian(2, 2) = 1.0;
        out.jacobian.block(2, 3, 1, m_) = k.at.rotation;
        out.planar.set(k.r, q[2] + k.at.rotation.dot(q.tail(m_)), k.rdot, v[2] + k.at.rotation.dot(v.tail(m_)));
        out.bias.setZero(3);
        out.bias.head<2>() = k.bias;
    }

    int node_count() const override { return static_cast<int>(model_.nodes.size()); }
    std::vector<double> node_parameters(int node) const override { return {model_.nodes[static_cast<size_t>(node)]}; }

private:
    struct Kinematics {
        ModalPoint at;
        Eigen::Vector2d r, rdot, bias;  // bias: rddot - L vdot
        Eigen::MatrixXd L;              // 2 x n
    };
    Kinematics kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, double x) const {
        Kinematics k;
        k.at = model_.at(x);
        const Eigen::Matrix2d A = rotation(q[2]), P = generator();
        const Eigen::Vector2d u = k.at.u0 + k.at.S * q.tail(m_), Spdot = k.at.S * v.tail(m_);
        const double w = v[2];
        k.L.setZero(2, coordinates());
        k.L.leftCols<2>().setIdentity();
        k.L.col(2) = A * P * u;
        k.L.rightCols(m_) = A * k.at.S;
        k.r = q.head<2>() + A * u;
        k.rdot = k.L * v;
        k.bias = A * (-w * w * u + 2.0 * w * P * Spdot);
        return k;
    }

    ModalModel model_;
    bool stiffening_ = false;
    int m_ = 0;
    Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
    double angle_ = 0.0;
};

std::unique_ptr<FlexibleBody> make_ffrf_body(const BodySpec& spec) { return std::make_unique<FfrfBody>(spec); }

}  // namespace
}  // namespace mbd

MBD_BODY_PLUGIN(ffrf_body, mbd::make_ffrf_body)
