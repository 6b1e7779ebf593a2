// Linearised equations of motion in independent coordinates: see linearisation.hpp.
#include <mbd/linearisation.hpp>

#include "analyses/cyclic_directions.hpp"
#include "analyses/reference_motion.hpp"

#include <mbd/body_poses.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/kit/velocity_transform.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

std::string column_name(const Model& model, int column) {
    const bool planar = model.dimension == Dimension::Planar;
    const int per_body = velocities_per_body(model.dimension);
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        const int k = column - f.v_offset;
        if (k >= 0 && k < f.size) return f.name + "." + f.body->coordinate_name(k);
    }
    static const char* planar_names[] = {"x", "y", "angle"};
    static const char* spatial_names[] = {"x", "y", "z", "rx", "ry", "rz"};  // rotations about body axes
    return model.bodies[column / per_body].name + "." +
           (planar ? planar_names[column % per_body] : spatial_names[column % per_body]);
}

// The flexible bodies' elastic forces Q_e (nv; zero in the rigid bodies' columns) at positions q.
Eigen::VectorXd flexible_elastic_forces(const Model& model, const Eigen::VectorXd& q) {
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(model.nv());
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        Eigen::VectorXd own(f.size);
        f.body->elastic_forces(q.segment(f.offset, f.size), own);
        Q.segment(f.v_offset, f.size) = own;
    }
    return Q;
}

// Their exact derivative dQ_e/dq (nv x nv, the bodies' own elastic_jacobian, sdk body.hpp).
Eigen::MatrixXd flexible_elastic_jacobian(const Model& model, const Eigen::VectorXd& q) {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(model.nv(), model.nv());
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        const int o = f.v_offset;
        f.body->elastic_jacobian(q.segment(f.offset, f.size), K.block(o, o, f.size, f.size));
    }
    return K;
}

// The reduced equations of motion of linearisation.hpp on a position partition (of the
// holonomic J) and a velocity partition (of every velocity row), with the actuators'
// generalized forces Q_u = J_s^T u (efforts along the joint coordinates).
class ReducedDynamics {
public:
    ReducedDynamics(ModelSystem& system, const State& reference, const CoordinatePartition& positions,
                    const CoordinatePartition& velocities, const Eigen::MatrixXd& actuator_forces)
        : system_(system), reference_(reference), positions_(positions), velocities_(velocities),
          actuator_forces_(actuator_forces) {}

    // The full consistent state at independent increments z and independent velocities w
    // (in the reference axes: v = T^T u with u_i = w, [J; A_nh] T^T u + C_t = 0).
    State state_at(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
        State s = positioned_at(z);
        const Eigen::MatrixXd T = reference_axes(system_.model(), s.q, reference_.q);
        Eigen::VectorXd u;
        dependent_velocities(Eigen::MatrixXd(J_ * T.transpose()), cv_.C_t, velocities_, w, u, ws_);
        s.v = T.transpose() * u;
        return s;
    }

    // The independent velocities that keep, at the positions shifted by z, the reference's
    // velocities in each body's own axes (cyclic_directions.hpp: the velocities a shift carries).
    Eigen::VectorXd carried_velocities(const Eigen::VectorXd& z) {
        const State s = positioned_at(z);
        Eigen::VectorXd w;
        gather(Eigen::VectorXd(reference_axes(system_.model(), s.q, reference_.q) * reference_.v), velocities_.independent, w);
        return w;
    }

    // vdot from [M J^T; J 0] [vdot; lambda] = [Q + Q_u u; gamma] over every row (Eq. 6.128);
    // minimum-norm in lambda, so redundant constraints are accepted.
    Eigen::VectorXd accelerations(const State& s, const Eigen::VectorXd& u) {
        const int nv = system_.nv();
        Eigen::VectorXd Q(nv);
        system_.generalized_forces(s, Q);
        if (u.size()) Q += actuator_forces_ * u;
        if (frozen_elastic_.size()) Q += frozen_elastic_ - flexible_elastic_forces(system_.model(), s.q);
        const Eigen::MatrixXd K = saddle_point_matrix(s);
        Eigen::VectorXd rhs(K.rows());
        rhs << Q, cv_.gamma;
        return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(K).solve(rhs).head(nv);
    }

    // The accelerations' change per generalized force at s (each column of `forces` one force,
    // the constraints' gamma left out): the linear part of accelerations() in Q.
    Eigen::MatrixXd force_response(const State& s, const Eigen::MatrixXd& forces) {
        const Eigen::MatrixXd K = saddle_point_matrix(s);
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(K.rows(), forces.cols());
        rhs.topRows(forces.rows()) = forces;
        return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(K).solve(rhs).topRows(forces.rows());
    }

    // While set, the rates take the flexible bodies' elastic forces as the reference's, whatever
    // the positions (linearise adds their exact derivative instead of differencing them).
    void freeze_elastic_forces(bool freeze) {
        const bool flexible = !system_.model().flexible_bodies.empty();
        frozen_elastic_ = freeze && flexible ? flexible_elastic_forces(system_.model(), reference_.q) : Eigen::VectorXd();
    }

    // (z', w') at (z, w, u): z' = (v - v0)_i, w' = (T vdot)_i (linearisation.hpp)
    Eigen::VectorXd rates(const Eigen::VectorXd& z, const Eigen::VectorXd& w, const Eigen::VectorXd& u) {
        const State s = state_at(z, w);
        const Eigen::VectorXd a = reference_axes(system_.model(), s.q, reference_.q) * accelerations(s, u);
        Eigen::VectorXd zdot, wdot;
        gather(Eigen::VectorXd(s.v - reference_.v), positions_.independent, zdot);
        gather(a, velocities_.independent, wdot);
        Eigen::VectorXd out(zdot.size() + wdot.size());
        out << zdot, wdot;
        return out;
    }

    // whether the last state's dependent positions converged (a far shift may not assemble)
    bool converged() const { return converged_; }

private:
    // the reference's positions shifted by z, the dependent ones by Newton-Raphson (J_ at them)
    State positioned_at(const Eigen::VectorXd& z) {
        State s = reference_;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(system_.nv());
        scatter(z, positions_.independent, dv);
        system_.advance_positions(s.q, dv);
        converged_ = correct_dependent_positions(system_, s, positions_, 1e-14, 30, cv_, J_, ws_);
        return s;
    }

    // [M J^T; J 0] at s over every row (cv_ keeps the rows and gamma)
    Eigen::MatrixXd saddle_point_matrix(const State& s) {
        const int nv = system_.nv();
        system_.constraints_with_velocity_rows(s, cv_, true);
        const int m = static_cast<int>(cv_.J.rows());
        system_.update_mass_matrix(s.q);  // a flexible body's mass that varies, at s (kit varying_mass.hpp)
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv + m, nv + m);
        K.topLeftCorner(nv, nv) = Eigen::MatrixXd(system_.mass_matrix());
        const Eigen::MatrixXd J(cv_.J);
        K.topRightCorner(nv, m) = J.transpose();
        K.bottomLeftCorner(m, nv) = J;
        return K;
    }

    ModelSystem& system_;
    const State& reference_;
    const CoordinatePartition& positions_;
    const CoordinatePartition& velocities_;
    const Eigen::MatrixXd& actuator_forces_;
    ConstraintValues cv_;
    VelocityTransformWorkspace ws_;
    Eigen::MatrixXd J_;
    Eigen::VectorXd frozen_elastic_;  // empty: the elastic forces at each state
    bool converged_ = true;
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

// Sixth-order central difference of f along one coordinate:
// (f3 - 9 f2 + 45 f1 - 45 f_1 + 9 f_2 - f_3) / 60h.
template <class F>
Eigen::VectorXd central_difference(F&& f, double h) {
    return (f(3 * h) - 9 * f(2 * h) + 45 * f(h) - 45 * f(-h) + 9 * f(-2 * h) - f(-3 * h)) / (60 * h);
}

// The partition of J and its velocity map (Eq. 6.80); throws when J is singular there.
CoordinatePartition partition_with_map(const ConstraintValues& cv, Eigen::MatrixXd& map, const char* rows) {
    const Eigen::MatrixXd J(cv.J);
    const CoordinatePartition partition = partition_coordinates(J);
    Eigen::VectorXd gamma_prime;
    VelocityTransformWorkspace ws;
    if (!velocity_transform(J, cv.gamma, partition, map, gamma_prime, ws))
        throw LinearisationError(std::string("the ") + rows +
                                 " constraints are singular at the reference state: no independent coordinates");
    return partition;
}

// No independent position: nothing moves, so there are no modes. Named by its cause: the
// drivers that prescribe the freedoms, or the joints that leave none.
void require_independent_positions(const Model& model, int independent) {
    if (independent > 0) return;
    const std::string where = model.source.empty() ? std::string() : model.source + ": ";
    if (model.drivers.empty())
        throw LinearisationError(where + "no freedom to linearise: the joints fix every body (0 independent "
                                         "coordinates), so the scene has no modes");
    std::string drivers;
    for (const Driver& d : model.drivers)
        drivers += std::string(drivers.empty() ? "" : ", ") + "'" + d.name + "' (joint '" + model.joints[d.joint].name + "')";
    const bool one = model.drivers.size() == 1;
    throw LinearisationError(
        where + "no freedom to linearise: the driver" + std::string(one ? " " : "s ") + drivers + (one ? " prescribes" : " prescribe") +
        " the motion of every coordinate the joints leave free (0 independent coordinates), so the scene has no "
        "modes; for the modes of the mechanism, remove the driver" + (one ? "" : "s") + " (the free mechanism) or make " +
        (one ? "it an actuator" : "them actuators") + " (actuators: [{name: " + model.drivers[0].name + ", joint: " +
        model.joints[model.drivers[0].joint].name + "}], its effort an input of B); for the driven motion itself, run "
        "`mbd kinematics`");
}

// Rates at the shifts +-shift along d (unit; the velocities carried along) against those at
// the reference: unchanged, to `tolerance`, outside the shifts Q (orthonormal states, n x s)?
bool unchanged_by_shift(ReducedDynamics& dynamics, const Eigen::MatrixXd& Q, const Eigen::VectorXd& d,
                        const Eigen::VectorXd& u0, const Eigen::VectorXd& rates0, double shift, double tolerance) {
    for (double s : {-shift, shift}) {
        const Eigen::VectorXd w = dynamics.carried_velocities(s * d);
        if (!dynamics.converged()) return false;
        Eigen::VectorXd change = dynamics.rates(s * d, w, u0) - rates0;
        if (!dynamics.converged()) return false;
        change -= Q * (Q.transpose() * change);
        if (!(change.cwiseAbs().maxCoeff() <= tolerance)) return false;
    }
    return true;
}

// The first-order change of the independent velocities that a position shift carries
// (k_w x k_z): each spatial body's angular velocity kept in its own axes, so that in the
// reference axes it changes by delta x wbar0 (delta its rotation increment).
Eigen::MatrixXd carried_velocity_map(const Model& model, const State& reference, const LinearModel& out,
                                     const std::vector<int>& velocity_columns) {
    const Eigen::Index kz = out.position_map.cols();
    Eigen::MatrixXd full = Eigen::MatrixXd::Zero(model.nv(), kz);
    if (model.dimension == Dimension::Spatial)
        for (int b = 0; b < model.body_count(); ++b) {
            const int o = model.v_offset(b) + 3;
            const Vec3 w0 = reference.v.segment<3>(o);
            for (Eigen::Index c = 0; c < kz; ++c)
                full.block<3, 1>(o, c) = Vec3(out.position_map.block<3, 1>(o, c)).cross(w0);
        }
    Eigen::MatrixXd W(velocity_columns.size(), kz);
    for (size_t r = 0; r < velocity_columns.size(); ++r) W.row(static_cast<Eigen::Index>(r)) = full.row(velocity_columns[r]);
    return W;
}

// The cyclic directions (cyclic_directions.hpp): the linear search, then each direction
// confirmed on the nonlinear equations by a finite shift (a direction that is only neutral
// to first order, like a bicycle's capsize mode at its critical speed, changes the rates at
// second order); the search repeated within the confirmed ones until all are.
void find_cyclic_directions(ReducedDynamics& dynamics, const LinearisationOptions& options, const Eigen::VectorXd& u0,
                            const Eigen::VectorXd& rates0, LinearModel& out) {
    const int kz = static_cast<int>(out.coordinates.size());
    const double scale = out.A.size() ? out.A.cwiseAbs().maxCoeff() : 0.0;
    const double linear_tolerance = options.cyclic_tolerance * std::max(scale, 1e-300);
    const double shift_tolerance = options.cyclic_tolerance * std::max(1.0, scale * options.cyclic_shift);
    const Eigen::MatrixXd W = out.carried_velocities;
    Eigen::MatrixXd within = Eigen::MatrixXd::Identity(kz, kz);
    while (true) {
        const Eigen::MatrixXd S = invariant_position_subspace(out.A, W, within, linear_tolerance);
        std::vector<int> pivots;
        const Eigen::MatrixXd E = reduced_echelon(S, pivots);
        Eigen::MatrixXd states(out.A.rows(), S.cols());
        states << S, W * S;
        const Eigen::MatrixXd Q = orthonormal_basis(states);
        Eigen::MatrixXd confirmed(kz, 0);
        for (Eigen::Index c = 0; c < E.cols(); ++c)
            if (unchanged_by_shift(dynamics, Q, E.col(c).normalized(), u0, rates0, options.cyclic_shift, shift_tolerance)) {
                confirmed.conservativeResize(kz, confirmed.cols() + 1);
                confirmed.rightCols(1) = E.col(c);
            }
        if (confirmed.cols() == E.cols()) {
            out.cyclic = E;
            out.cyclic_pivots = pivots;
            return;
        }
        within = confirmed;
    }
}

// A's columns by differences of the rates (sixth order), with the flexible bodies' elastic
// forces held at the reference's: their stiffness is exact (add_elastic_stiffness), and
// differencing it would leave the round-off of K q (stiff axial terms) in every column.
void differenced_columns(ReducedDynamics& dynamics, const LinearisationOptions& options, const Eigen::VectorXd& z0,
                         const Eigen::VectorXd& w0, const Eigen::VectorXd& u0, Eigen::MatrixXd& A) {
    const int kz = static_cast<int>(z0.size()), kw = static_cast<int>(w0.size());
    dynamics.freeze_elastic_forces(true);
    for (int c = 0; c < kz; ++c) {
        const Eigen::VectorXd e = Eigen::VectorXd::Unit(kz, c);
        A.col(c) = central_difference([&](double d) { return dynamics.rates(z0 + d * e, w0, u0); }, options.step);
    }
    for (int c = 0; c < kw; ++c) {
        const Eigen::VectorXd e = Eigen::VectorXd::Unit(kw, c);
        const double hv = options.velocity_step * std::max(1.0, std::abs(w0[c]));
        A.block(kz, kz + c, kw, 1) = central_difference(
            [&](double d) { return Eigen::VectorXd(dynamics.rates(z0, w0 + d * e, u0).tail(kw)); }, hv);
    }
    dynamics.freeze_elastic_forces(false);
}

// The elastic forces' part of A: d(vdot)/dz = P (dQ_e/dq) (dq/dz), P the accelerations' response
// to a force at the reference (the rest of d(P Q_e)/dz, with Q_e held, is in the differences);
// dq/dz is the position map, and the reference axes are the identity at the reference.
void add_elastic_stiffness(ReducedDynamics& dynamics, const Model& model, const State& reference, LinearModel& out,
                           const std::vector<int>& velocity_columns) {
    if (model.flexible_bodies.empty()) return;
    const Eigen::Index kz = out.position_map.cols();
    const Eigen::MatrixXd change = dynamics.force_response(
        reference, flexible_elastic_jacobian(model, reference.q) * out.position_map);
    for (size_t r = 0; r < velocity_columns.size(); ++r)
        out.A.block(kz + static_cast<Eigen::Index>(r), 0, 1, kz) += change.row(velocity_columns[r]);
}

}  // namespace

void require_freedom(ModelSystem& system, const State& state) {
    ConstraintValues holonomic;
    system.constraints(state, holonomic, true);
    require_independent_positions(system.model(),
                                  static_cast<int>(partition_coordinates(Eigen::MatrixXd(holonomic.J)).independent.size()));
}

void require_linearisable(const Model& model) {
    // the reduced accelerations solve no reaction loads: such a friction would act at load 0
    for (const ForceInstance& f : model.forces)
        if (f.load_joint >= 0)
            throw LinearisationError(f.where + ": force '" + f.name + "' (type " + f.type +
                                     ") takes its load from the reaction of joint '" + model.joints[f.load_joint].name +
                                     "', which mbd modes does not solve (and friction is not smooth where it "
                                     "sticks); give it a fixed 'normal_force', or leave it out");
}

LinearModel linearise(ModelSystem& system, const State& start, const std::vector<ActuatorInfo>& actuators,
                      const LinearisationOptions& options) {
    require_linearisable(system.model());
    LinearModel out;
    State reference = start;
    system.assemble(reference, true);
    system.consistent_velocities(reference, true);
    out.reference = reference;

    // positions: the holonomic rows; velocities: those and the velocity-level (nonholonomic) rows
    ConstraintValues holonomic, all_rows;
    system.constraints(reference, holonomic, true);
    system.constraints_with_velocity_rows(reference, all_rows, true);
    const CoordinatePartition positions = partition_with_map(holonomic, out.position_map, "position");
    require_independent_positions(system.model(), static_cast<int>(positions.independent.size()));
    const CoordinatePartition velocities = partition_with_map(all_rows, out.velocity_map, "velocity");
    const int kz = static_cast<int>(positions.independent.size());
    const int kw = static_cast<int>(velocities.independent.size());
    out.columns = positions.independent;
    out.velocity_columns = velocities.independent;
    for (int c : positions.independent) out.coordinates.push_back(column_name(system.model(), c));
    for (int c : velocities.independent) out.velocity_coordinates.push_back(column_name(system.model(), c));
    Eigen::MatrixXd joint_rows;
    joint_coordinate_rows(system, reference, out, joint_rows);
    out.joint_map = joint_rows * out.position_map;

    const Eigen::MatrixXd Qu = actuator_force_map(system, reference, actuators);
    for (const ActuatorInfo& a : actuators) out.inputs.push_back(a.name);
    ReducedDynamics dynamics(system, reference, positions, velocities, Qu);
    const Eigen::VectorXd z0 = Eigen::VectorXd::Zero(kz), u0 = Eigen::VectorXd::Zero(Qu.cols());
    Eigen::VectorXd w0;
    gather(reference.v, velocities.independent, w0);

    // a steady motion keeps its independent velocities: w' = 0
    const Eigen::VectorXd rates0 = dynamics.rates(z0, w0, u0);
    out.residual = kw ? rates0.tail(kw).cwiseAbs().maxCoeff() : 0.0;
    if (!(out.residual <= options.residual_tolerance))
        throw LinearisationError("the reference state is not an equilibrium or steady motion: the accelerations are " +
                                 format_number(out.residual) + " (max |vdot| of the independent coordinates, tolerance " +
                                 format_number(options.residual_tolerance) +
                                 "); start from a static equilibrium (--about statics) or a steady motion");
    require_steady_motion(
        system, reference, [&](const State& s) { return dynamics.accelerations(s, u0); }, options.residual_tolerance);

    const int n = kz + kw;
    out.A = Eigen::MatrixXd::Zero(n, n);
    differenced_columns(dynamics, options, z0, w0, u0, out.A);
    add_elastic_stiffness(dynamics, system.model(), reference, out, velocities.independent);
    // z' = (v - v0)_i is linear in w at the reference: the rows of the velocity map
    for (int r = 0; r < kz; ++r) out.A.block(r, kz, 1, kw) = out.velocity_map.row(positions.independent[r]);
    out.B = Eigen::MatrixXd::Zero(n, Qu.cols());
    for (int a = 0; a < Qu.cols(); ++a)
        out.B.block(kz, a, kw, 1) = dynamics.rates(z0, w0, Eigen::VectorXd::Unit(Qu.cols(), a)).tail(kw) - rates0.tail(kw);
    out.carried_velocities = carried_velocity_map(system.model(), reference, out, velocities.independent);
    find_cyclic_directions(dynamics, options, u0, rates0, out);
    return out;
}

}  // namespace mbd
