// Joint reactions from Lagrange multipliers (Shabana, Computational Dynamics,
// Sec. 6.6 and Sec. 6.8, Eqs. 6.146-6.148), header-only so that every analysis
// (forward dynamics, statics, inverse dynamics) computes them the same way.
//
// The generalized constraint forces are Q_c = -J^T lambda (book Eq. 6.128); per joint
// k and body i, (Q_c^i)_k = -(C_k)_{q^i}^T lambda_k (Eq. 6.146) is a force at the mass
// centre and a moment (planar: about z; spatial: in BODY axes, because the velocity
// columns are (dR, dpi_bar)). Moving it to the joint point P (the origin of the joint's
// marker on that body, u_P = A u_bar_P) gives the equipollent force and torque at
// the joint (Eq. 6.147): F = Q_R, T_P = T_cm - u_P x F (Eq. 6.148 by virtual work).
//
// A joint's velocity-level rows (A v = b, a wheel's no-slip condition) carry reactions
// the same way, Q_c = -A^T mu (their multipliers mu follow the drivers' in lambda), and
// count in the joint's reaction when lambda has them.
//
// A joint at a flexible body holds, in that body's slot, the material frame at the joint
// (System::joint_material_frame): its reaction is -J_frame^T lambda on the frame's velocities,
// a force at the frame's origin and a moment, moved to the joint point the same way (the
// mapped rows J_frame G would spread it over the body's coordinates instead).
//
// A driver's row (s(q) - f(t) = 0) adds the actuator effort; it is reported
// separately (driver_reactions) so that a joint's reaction is what its bearing carries
// and the driver's is what the motor supplies.
#pragma once

#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace mbd {

// The reaction of one joint (or driver) on one of its bodies, at the joint point.
struct BodyReaction {
    int body = -1;                       // body index (the ground is never listed)
    bool material_frame = false;         // a flexible body's material frame (body stays -1)
    Vec3 force = Vec3::Zero();           // world axes (planar: z = 0)
    Vec3 torque = Vec3::Zero();          // world axes, about the joint point (planar: only z)
    Vec3 force_joint = Vec3::Zero();     // the same in the joint frame (this body's marker axes)
    Vec3 torque_joint = Vec3::Zero();
    Vec3 point = Vec3::Zero();           // the joint point P in world
    // The generalized constraint force on the body's velocity rows (Eq. 6.146):
    // planar (Fx, Fy, M_z) at the mass centre; spatial (F world, M body axes).
    Eigen::Matrix<double, 6, 1> generalized = Eigen::Matrix<double, 6, 1>::Zero();
    // Whether a reaction is carried here: a rigid body or a flexible body's material frame.
    bool carried() const { return body >= 0 || material_frame; }
};

struct JointReaction {
    std::string name;                    // joint (or driver) name
    int element = -1;                    // joint or driver index
    bool driver = false;
    std::vector<int> bodies;             // the element's bodies, as in JointInfo (-1 ground)
    std::vector<BodyReaction> on;        // one entry per element body, same order (ground: body = -1, zero)
};

namespace reactions_detail {

// Pose of a body at state: rotation A (3x3, planar embedded) and mass centre R.
inline void body_pose(System& system, const State& state, int body, Mat3& A, Vec3& R) {
    if (system.dimension() == Dimension::Planar) {
        const int o = 3 * body;
        R = Vec3(state.q[o], state.q[o + 1], 0.0);
        A = Mat3::Identity();
        A.topLeftCorner<2, 2>() = planar_rotation(state.q[o + 2]);
    } else {
        const int o = 7 * body;
        R = state.q.segment<3>(o);
        const Vec4 p = state.q.segment<4>(o + 3);
        A = rotation_from_euler_parameters(p / p.norm());
    }
}

// Marker axes in body coordinates (planar: rotation by the marker angle).
inline Mat3 marker_axes(System& system, const Marker& m) {
    if (system.dimension() == Dimension::Planar) {
        Mat3 a = Mat3::Identity();
        a.topLeftCorner<2, 2>() = planar_rotation(m.angle);
        return a;
    }
    return m.A_bar;
}

// Rows [first, first + count) of J and lambda.
struct RowRange {
    int first = 0;
    int count = 0;
};

// Reactions on the bodies of one element from its row ranges of J and lambda.
// The reaction on a flexible body's material frame at joint `joint`'s slot k from the joint's
// rows [first, first + rows) of lambda (Eq. 6.146 on the frame's velocities); false for a
// rigid slot (or the ground).
inline bool material_frame_reaction(System& system, const State& state, int joint, int driver, int k, int first,
                                    const Eigen::VectorXd& lambda, Mat3& A, Vec3& R,
                                    Eigen::Matrix<double, 6, 1>& g) {
    Eigen::MatrixXd J_frame;
    const bool flexible = driver >= 0 ? system.driver_material_frame(state, driver, k, A, R, J_frame)
                                      : joint >= 0 && system.joint_material_frame(state, joint, k, A, R, J_frame);
    if (!flexible) return false;
    g.setZero();
    g.head(J_frame.cols()) = -J_frame.transpose() * lambda.segment(first, J_frame.rows());
    return true;
}

// joint_index: the joint whose rows the first range holds, for its slots on flexible bodies;
// driver_index: the driver whose row it is instead (-1: none).
inline JointReaction element_reaction(System& system, const State& state,
                                      const Eigen::SparseMatrix<double, Eigen::RowMajor>& J,
                                      const Eigen::VectorXd& lambda, const JointInfo& joint,
                                      std::initializer_list<RowRange> ranges, int joint_index = -1,
                                      int driver_index = -1) {
    const bool planar = system.dimension() == Dimension::Planar;
    const int nvb = velocities_per_body(system.dimension());
    JointReaction out;
    out.bodies = joint.bodies;
    out.on.resize(joint.bodies.size());
    for (size_t k = 0; k < joint.bodies.size(); ++k) {
        BodyReaction& r = out.on[k];
        const int body = joint.bodies[k];
        r.body = body;
        const Marker& marker = joint.markers.at(k);
        Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
        Mat3 A;
        Vec3 R;
        if (body < 0) {
            r.material_frame = material_frame_reaction(system, state, joint_index, driver_index, static_cast<int>(k),
                                                       ranges.begin()->first, lambda, A, R, g);
            if (!r.material_frame) {
                r.point = marker.u_bar;  // the ground frame is the world
                if (planar) r.point.z() = 0.0;
                continue;
            }
        } else {
            // generalized constraint force -J_k^T lambda_k on this body's columns (Eq. 6.146)
            const int c0 = body * nvb;
            for (const RowRange& range : ranges) {
                for (int row = range.first; row < range.first + range.count; ++row) {
                    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(J, row); it; ++it) {
                        const int c = static_cast<int>(it.col());
                        if (c >= c0 && c < c0 + nvb) g[c - c0] -= it.value() * lambda[row];
                    }
                }
            }
            body_pose(system, state, body, A, R);
        }
        r.generalized = g;
        Vec3 u_bar = marker.u_bar;
        if (planar) u_bar.z() = 0.0;
        const Vec3 u = A * u_bar;  // u_P = A u_bar_P
        r.point = R + u;
        Vec3 torque_cm;
        if (planar) {
            r.force = Vec3(g[0], g[1], 0.0);
            torque_cm = Vec3(0.0, 0.0, g[2]);
        } else {
            r.force = g.head<3>();
            torque_cm = A * g.tail<3>();  // the generalized moment is in body axes
        }
        // move to the joint point: T_P = T_cm - u_P x F (Eq. 6.147)
        r.torque = torque_cm - u.cross(r.force);
        const Mat3 frame = A * marker_axes(system, marker);  // joint frame on this body, world axes
        r.force_joint = frame.transpose() * r.force;
        r.torque_joint = frame.transpose() * r.torque;
    }
    return out;
}

inline void check_sizes(System& system, const State& state, const Eigen::VectorXd& lambda) {
    if (state.q.size() != system.nq() || state.v.size() != system.nv())
        throw std::invalid_argument("joint_reactions: the state does not match the system");
    const long n = lambda.size();
    if (n != system.constraint_rows(true) && n != system.constraint_rows(false) &&
        n != system.constraint_rows(true) + system.velocity_constraint_rows())
        throw std::invalid_argument("joint_reactions: " + std::to_string(lambda.size()) +
                                    " multipliers for " + std::to_string(system.constraint_rows(true)) +
                                    " constraint rows");
}

// lambda holds the velocity-level rows' multipliers too
inline bool has_velocity_rows(System& system, const Eigen::VectorXd& lambda) {
    return system.velocity_constraint_rows() > 0 &&
           lambda.size() == system.constraint_rows(true) + system.velocity_constraint_rows();
}

}  // namespace reactions_detail

// Reactions of every joint on each of its bodies (joint rows only), in scene order.
// lambda holds one multiplier per constraint row (joints then drivers, or joints only;
// or joints, drivers and the velocity-level rows).
inline std::vector<JointReaction> joint_reactions(System& system, const State& state,
                                                  const Eigen::VectorXd& lambda) {
    reactions_detail::check_sizes(system, state, lambda);
    const bool velocity_rows = reactions_detail::has_velocity_rows(system, lambda);
    const bool drivers = velocity_rows || (lambda.size() == system.constraint_rows(true) && system.driver_count() > 0);
    ConstraintValues cv;
    if (velocity_rows)
        system.constraints_with_velocity_rows(state, cv, true);
    else
        system.constraints(state, cv, drivers);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> J = cv.J;
    const int first_velocity_row = system.constraint_rows(true);
    std::vector<JointReaction> out;
    out.reserve(system.joint_count());
    for (int j = 0; j < system.joint_count(); ++j) {
        const JointInfo& info = system.joint(j);
        const reactions_detail::RowRange velocity{first_velocity_row + info.velocity_row_offset,
                                                  velocity_rows ? info.velocity_rows : 0};
        JointReaction r =
            reactions_detail::element_reaction(system, state, J, lambda, info, {{info.first_row, info.rows}, velocity}, j);
        r.name = info.name;
        r.element = j;
        out.push_back(std::move(r));
    }
    return out;
}

// The reaction on the joint's second body at its joint point (world axes), or, when that body is
// the ground, minus the reactions on the others moved to its point (a joint's constraint forces
// are self-equilibrated): what `mbd statics` and `mbd simulate --reactions` report.
inline void second_body_load(const JointReaction& r, Vec3& force, Vec3& torque) {
    force.setZero();
    torque.setZero();
    if (r.on.size() >= 2 && r.on[1].carried()) {
        force = r.on[1].force;
        torque = r.on[1].torque;
    } else if (r.on.size() >= 2) {
        const Vec3 P = r.on[1].point;
        for (const BodyReaction& b : r.on) {
            if (!b.carried()) continue;
            force -= b.force;
            torque -= b.torque + (b.point - P).cross(b.force);
        }
    } else if (!r.on.empty()) {
        force = r.on[0].force;
        torque = r.on[0].torque;
    }
}

// The actuator effort of every driver on the bodies of its joint (empty when lambda
// has no driver rows). For a revolute driver this is the motor torque pair.
inline std::vector<JointReaction> driver_reactions(System& system, const State& state,
                                                   const Eigen::VectorXd& lambda) {
    reactions_detail::check_sizes(system, state, lambda);
    std::vector<JointReaction> out;
    if (lambda.size() < system.constraint_rows(true) || system.driver_count() == 0) return out;
    ConstraintValues cv;
    if (reactions_detail::has_velocity_rows(system, lambda))
        system.constraints_with_velocity_rows(state, cv, true);
    else
        system.constraints(state, cv, true);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> J = cv.J;
    for (int d = 0; d < system.driver_count(); ++d) {
        const DriverInfo& info = system.driver(d);
        JointReaction r = reactions_detail::element_reaction(system, state, J, lambda, system.joint(info.joint),
                                                             {{info.row, 1}}, -1, d);
        r.name = info.name;
        r.element = d;
        r.driver = true;
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace mbd
