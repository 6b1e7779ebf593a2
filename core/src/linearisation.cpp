// Linearised equations of motion in independent coordinates: see linearisation.hpp.
#include <mbd/linearisation.hpp>

#include <mbd/body_poses.hpp>
#include <mbd/sdk/partition.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/sdk/velocity_transform.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

std::string column_name(const Model& model, int column) {
    const bool planar = model.dimension == Dimension::Planar;
    const int per_body = velocities_per_body(model.dimension);
    static const char* planar_names[] = {"x", "y", "angle"};
    static const char* spatial_names[] = {"x", "y", "z", "rx", "ry", "rz"};  // rotations about body axes
    return model.bodies[column / per_body].name + "." +
           (planar ? planar_names[column % per_body] : spatial_names[column % per_body]);
}

// The reduced equations of motion of linearisation.hpp on one partition, with the
// actuators' generalized forces Q_u = J_s^T u (efforts along the joint coordinates).
class ReducedDynamics {
public:
    ReducedDynamics(ModelSystem& system, const State& reference, const CoordinatePartition& partition,
                    const Eigen::MatrixXd& actuator_forces)
        : system_(system), reference_(reference), partition_(partition), actuator_forces_(actuator_forces) {}

    // The full consistent state at independent increments z and independent velocities w.
    State state_at(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
        State s = reference_;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(system_.nv());
        scatter(z, partition_.independent, dv);
        system_.advance_positions(s.q, dv);
        Eigen::MatrixXd J;
        correct_dependent_positions(system_, s, partition_, 1e-14, 30, cv_, J, ws_);
        dependent_velocities(J, cv_.C_t, partition_, w, s.v, ws_);
        return s;
    }

    // vdot from [M J^T; J 0] [vdot; lambda] = [Q + Q_u u; gamma] (Eq. 6.128); minimum-norm
    // in lambda, so redundant constraints are accepted.
    Eigen::VectorXd accelerations(const State& s, const Eigen::VectorXd& u) {
        const int nv = system_.nv();
        system_.constraints(s, cv_, true);
        const int m = static_cast<int>(cv_.J.rows());
        Eigen::VectorXd Q(nv);
        system_.generalized_forces(s, Q);
        if (u.size()) Q += actuator_forces_ * u;
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv + m, nv + m);
        K.topLeftCorner(nv, nv) = Eigen::MatrixXd(system_.mass_matrix());
        const Eigen::MatrixXd J(cv_.J);
        K.topRightCorner(nv, m) = J.transpose();
        K.bottomLeftCorner(m, nv) = J;
        Eigen::VectorXd rhs(nv + m);
        rhs << Q, cv_.gamma;
        return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(K).solve(rhs).head(nv);
    }

    // w' = vdot_i at (z, w, u)
    Eigen::VectorXd independent_accelerations(const Eigen::VectorXd& z, const Eigen::VectorXd& w,
                                              const Eigen::VectorXd& u) {
        Eigen::VectorXd a_i;
        gather(accelerations(state_at(z, w), u), partition_.independent, a_i);
        return a_i;
    }

private:
    ModelSystem& system_;
    const State& reference_;
    const CoordinatePartition& partition_;
    const Eigen::MatrixXd& actuator_forces_;
    ConstraintValues cv_;
    VelocityTransformWorkspace ws_;
};

// nv x actuators: column a is J_s^T of actuator a's joint coordinate at `state`.
Eigen::MatrixXd actuator_force_map(ModelSystem& system, const State& state, const std::vector<ActuatorInfo>& actuators) {
    const Model& model = system.model();
    const int per_body = velocities_per_body(model.dimension);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(system.nv(), static_cast<Eigen::Index>(actuators.size()));
    BodyPoses poses(model);
    poses.update(state);
    for (size_t a = 0; a < actuators.size(); ++a) {
        const JointInfo& info = system.joint(actuators[a].joint);
        if (!info.joint->has_coordinate())
            throw LinearisationError("actuator '" + actuators[a].name + "': joint '" + info.name +
                                     "' has no coordinate to act along");
        CoordinateEval ce;
        ce.J.setZero(per_body * static_cast<int>(info.bodies.size()));
        info.joint->coordinate(poses.view(info.bodies, state.t), ce);
        for (size_t k = 0; k < info.bodies.size(); ++k)
            if (info.bodies[k] != kGround)
                G.col(static_cast<Eigen::Index>(a)).segment(per_body * info.bodies[k], per_body) +=
                    ce.J.segment(per_body * static_cast<int>(k), per_body).transpose();
    }
    return G;
}

// Joints with a coordinate, and their rates per unit velocity (J_s over all nv columns).
void joint_coordinate_rows(ModelSystem& system, const State& state, LinearModel& out, Eigen::MatrixXd& rows) {
    std::vector<ActuatorInfo> along;
    for (int j = 0; j < system.joint_count(); ++j)
        if (system.joint(j).joint->has_coordinate()) {
            along.push_back({system.joint(j).name, j});
            out.joint_coordinates.push_back(system.joint(j).name);
        }
    rows = actuator_force_map(system, state, along).transpose();
}

// Fourth-order central difference of f along one coordinate: (-f2 + 8 f1 - 8 f_1 + f_2) / 12h.
template <class F>
Eigen::VectorXd central_difference(F&& f, double h) {
    return (-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h);
}

void refuse_rotating_spatial_bodies(const ModelSystem& system, const State& reference) {
    if (system.dimension() != Dimension::Spatial) return;
    for (int b = 0; b < system.body_count(); ++b)
        if (reference.v.segment<3>(6 * b + 3).norm() > 0.0)
            throw LinearisationError("body '" + system.model().bodies[b].name +
                                     "' rotates in the reference state: linearising about a steady motion with "
                                     "rotating spatial bodies is not supported; linearise about a static "
                                     "equilibrium (--about statics) instead");
}

}  // namespace

LinearModel linearise(ModelSystem& system, const State& start, const std::vector<ActuatorInfo>& actuators,
                      const LinearisationOptions& options) {
    // the reduced coordinates here are the holonomic ones (v_i of J alone)
    require_holonomic(system.model(), "the linearisation (mbd modes)",
                      "simulate the motion (`mbd simulate`) and study it in the time domain instead");
    LinearModel out;
    State reference = start;
    system.assemble(reference, true);
    system.consistent_velocities(reference, true);
    refuse_rotating_spatial_bodies(system, reference);
    out.reference = reference;

    ConstraintValues cv;
    system.constraints(reference, cv, true);
    const Eigen::MatrixXd J(cv.J);
    const CoordinatePartition partition = partition_coordinates(J);
    const int k = static_cast<int>(partition.independent.size());
    out.columns = partition.independent;
    for (int c : partition.independent) out.coordinates.push_back(column_name(system.model(), c));
    Eigen::VectorXd gamma_prime;
    VelocityTransformWorkspace ws;
    if (!velocity_transform(J, cv.gamma, partition, out.velocity_map, gamma_prime, ws))
        throw LinearisationError("the constraints are singular at the reference state: no independent coordinates");
    Eigen::MatrixXd joint_rows;
    joint_coordinate_rows(system, reference, out, joint_rows);
    out.joint_map = joint_rows * out.velocity_map;

    const Eigen::MatrixXd Qu = actuator_force_map(system, reference, actuators);
    for (const ActuatorInfo& a : actuators) out.inputs.push_back(a.name);
    ReducedDynamics dynamics(system, reference, partition, Qu);
    const Eigen::VectorXd z0 = Eigen::VectorXd::Zero(k), u0 = Eigen::VectorXd::Zero(Qu.cols());
    Eigen::VectorXd w0;
    gather(reference.v, partition.independent, w0);

    // a steady motion keeps its independent velocities: vdot_i = 0
    const Eigen::VectorXd a_i0 = dynamics.independent_accelerations(z0, w0, u0);
    out.residual = k ? a_i0.cwiseAbs().maxCoeff() : 0.0;
    if (!(out.residual <= options.residual_tolerance))
        throw LinearisationError("the reference state is not an equilibrium or steady motion: the accelerations are " +
                                 format_number(out.residual) + " (max |vdot| of the independent coordinates, tolerance " +
                                 format_number(options.residual_tolerance) +
                                 "); start from a static equilibrium (--about statics) or a steady motion");

    out.A = Eigen::MatrixXd::Zero(2 * k, 2 * k);
    out.A.topRightCorner(k, k).setIdentity();  // z' = w
    for (int c = 0; c < k; ++c) {
        Eigen::VectorXd e = Eigen::VectorXd::Unit(k, c);
        out.A.block(k, c, k, 1) = central_difference(
            [&](double d) { return dynamics.independent_accelerations(z0 + d * e, w0, u0); }, options.step);
        const double hv = options.step * std::max(1.0, std::abs(w0[c]));
        out.A.block(k, k + c, k, 1) = central_difference(
            [&](double d) { return dynamics.independent_accelerations(z0, w0 + d * e, u0); }, hv);
    }
    out.B = Eigen::MatrixXd::Zero(2 * k, Qu.cols());
    for (int a = 0; a < Qu.cols(); ++a)
        out.B.block(k, a, k, 1) =
            dynamics.independent_accelerations(z0, w0, Eigen::VectorXd::Unit(Qu.cols(), a)) - a_i0;
    return out;
}

}  // namespace mbd
