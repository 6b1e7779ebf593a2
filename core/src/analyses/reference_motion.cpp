// Steady motions of the linearisation: see reference_motion.hpp.
#include "analyses/reference_motion.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace mbd {

Eigen::MatrixXd reference_axes(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& q0) {
    const int nv = model.nv();
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(nv, nv);
    if (model.dimension != Dimension::Spatial) return T;
    for (int b = 0; b < model.body_count(); ++b) {
        const int o = model.q_offset(b) + 3;
        const Mat3 A = rotation_from_euler_parameters(q.segment<4>(o).normalized());
        const Mat3 A0 = rotation_from_euler_parameters(q0.segment<4>(o).normalized());
        T.block<3, 3>(model.v_offset(b) + 3, model.v_offset(b) + 3) = A0.transpose() * A;
    }
    return T;
}

namespace {

// A body turning about a body-fixed axis e must look the same all along its turn for the
// linearisation to be time-invariant: its inertia symmetric about e (e a principal axis, the
// two other moments equal), i.e. unchanged by a quarter turn about e.
void require_symmetric_spin(const Model& model, const State& reference, double still) {
    if (model.dimension != Dimension::Spatial) return;
    for (int b = 0; b < model.body_count(); ++b) {
        const Vec3 w = reference.v.segment<3>(model.v_offset(b) + 3);
        if (w.norm() <= still) continue;
        const Mat3& J = model.bodies[b].inertia;
        const Mat3 quarter = Eigen::AngleAxisd(M_PI / 2, w.normalized()).toRotationMatrix();
        if ((quarter * J * quarter.transpose() - J).norm() > 1e-9 * std::max(J.norm(), 1e-300))
            throw LinearisationError(
                "body '" + model.bodies[b].name +
                "' turns in the reference state about an axis its inertia is not symmetric about: the motion "
                "does not look the same all along it, so its linearisation would vary in time (mbd modes "
                "linearises steady motions whose turning bodies are symmetric about their axis of rotation, "
                "like a wheel about its axle); linearise about a static equilibrium (--about statics) instead");
    }
}

}  // namespace

void require_steady_motion(const ModelSystem& system, const State& reference,
                           const std::function<Eigen::VectorXd(const State&)>& vdot, double tolerance) {
    const Model& model = system.model();
    if (reference.v.cwiseAbs().maxCoeff() == 0.0) return;  // at rest: the residual check is enough
    // rates below this are the rounding of consistent_velocities, not a turn
    const double still = 1e-12 * reference.v.cwiseAbs().maxCoeff();
    require_symmetric_spin(model, reference, still);
    double fastest = 0.0;
    const int per_body = velocities_per_body(model.dimension);
    for (int b = 0; b < model.body_count(); ++b) {
        const int o = model.v_offset(b) + (model.dimension == Dimension::Spatial ? 3 : 2);
        fastest = std::max(fastest, reference.v.segment(o, per_body == 6 ? 3 : 1).norm());
    }
    const double tau = fastest > still ? 1.0 / fastest : 1.0;
    for (double t : {0.0, tau}) {
        State s = reference;
        system.advance_positions(s.q, reference.v * t);
        s.t = reference.t + t;
        const Eigen::VectorXd a = vdot(s);
        Eigen::Index worst = 0;
        const double residual = a.cwiseAbs().maxCoeff(&worst);
        if (!(residual <= tolerance)) {
            const int body = static_cast<int>(worst) / per_body;
            throw LinearisationError(
                "the reference state moves but is not a steady motion: " +
                std::string(t == 0.0 ? "at the reference" : "after " + format_number(t) + " s along it") +
                " the accelerations reach " + format_number(residual) + " (body '" + model.bodies[body].name +
                "', tolerance " + format_number(tolerance) +
                "); a steady motion keeps every body's velocity constant (uniform translation, a constant "
                "rotation rate about a body-fixed axis, the dynamics the same all along it): start from one, "
                "or from a static equilibrium (--about statics)");
        }
    }
}

}  // namespace mbd
