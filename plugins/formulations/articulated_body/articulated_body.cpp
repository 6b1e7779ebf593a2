// The articulated-body formulation of a tree in joint coordinates: see articulated_body.hpp.
#include "articulated_body.hpp"
#include <mbd/kit/non_finite_motion.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mbd::articulated {

// Phi x, Phi^T f and P += Phi^T X Phi (X symmetric) with Phi = [[I, S], [0, E]], by 3x3 blocks
Vec6 ArticulatedBody::phi_mul(const Body& c, const Vec6& x) {
    Vec6 out;
    out.head<3>() = x.head<3>() + c.S * x.tail<3>();
    out.tail<3>() = c.E * x.tail<3>();
    return out;
}

Vec6 ArticulatedBody::phiT_mul(const Body& c, const Vec6& f) {
    Vec6 out;
    out.head<3>() = f.head<3>();
    out.tail<3>() = c.S.transpose() * f.head<3>() + c.E.transpose() * f.tail<3>();
    return out;
}

void ArticulatedBody::add_phiT_X_phi(const Body& c, const Mat6& X, Mat6& P) {
    const Mat3 X11 = X.topLeftCorner<3, 3>(), X12 = X.topRightCorner<3, 3>(), X21 = X.bottomLeftCorner<3, 3>(),
               X22 = X.bottomRightCorner<3, 3>();
    const Mat3 Y12 = X11 * c.S + X12 * c.E;
    P.topLeftCorner<3, 3>() += X11;
    P.topRightCorner<3, 3>() += Y12;
    P.bottomLeftCorner<3, 3>() += Y12.transpose();
    P.bottomRightCorner<3, 3>() += c.S.transpose() * Y12 + c.E.transpose() * (X21 * c.S + X22 * c.E);
}

Vec6 ArticulatedBody::to6(const Eigen::VectorXd& x, int body) const {
    Vec6 out = Vec6::Zero();
    if (planar_) {
        out[0] = x[3 * body];
        out[1] = x[3 * body + 1];
        out[5] = x[3 * body + 2];
    } else {
        out = x.segment<6>(6 * body);
    }
    return out;
}

void ArticulatedBody::bind(System& system, const FormulationOptions& /*options*/) {
    std::string reason;
    if (!recursive_embedding_possible(system, &reason))
        throw InputError("", "embedding formulation: the recursive path needs a tree of joints in relative coordinates "
                             "whose drivers drive joints of one freedom; this scene has " + reason +
                             " (use path: closure, dense or auto)");
    build(system, analyse_topology(system));
    prescribe_driven_joints(system);
}

void ArticulatedBody::prescribe_driven_joints(System& system) {
    std::vector<int> edge_of_joint(system.joint_count(), -1);
    for (size_t i = 0; i < edges_.size(); ++i)
        if (edges_[i].joint >= 0) edge_of_joint[edges_[i].joint] = static_cast<int>(i);
    for (int d = 0; d < system.driver_count(); ++d) {
        const int i = edge_of_joint.at(system.driver(d).joint);
        Edge& e = edges_.at(i);
        e.prescribed = static_cast<int>(prescribed_.size());
        prescribed_.push_back({d, i, e.freedoms.at(0).s, e.freedoms.at(0).u});
    }
    if (!prescribed_.empty()) {
        // the driver's coordinate s(q) against the edge's, at the assembled initial state: the
        // rate d s(q) / d u (the driver's row times the child's partial velocity; the parent does
        // not move with u) is +-1, and s_edge - sign s(q) is the constant offset (modulo 2 pi for
        // an angle, which the kinematics do not see)
        const State s0 = assembled_initial_state(system);
        joint_coordinates(s0);
        ConstraintValues cv;
        system.constraints(s0, cv, true);
        const int nvb = planar_ ? 3 : 6;
        for (Prescribed& p : prescribed_) {
            const Edge& e = edges_[p.edge];
            const DriverInfo& driver = system.driver(p.driver);
            const auto h = H(e).col(0);
            double rate = 0.0;
            for (int k = 0; k < nvb; ++k)
                for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, e.body * nvb + k); it; ++it)
                    if (it.row() == driver.row) rate += it.value() * h[planar_ && k == 2 ? 5 : k];
            if (!(std::abs(std::abs(rate) - 1.0) < 1e-6))
                throw InputError("", "embedding formulation, recursive path: driver '" + driver.name + "' on joint '" +
                                         system.joint(e.joint).name + "': its coordinate moves " + std::to_string(rate) +
                                         " per unit of the joint's relative motion, not +-1; use path: closure");
            p.sign = rate > 0.0 ? 1.0 : -1.0;
            p.offset = s_[p.s] - p.sign * (cv.C[driver.row] + system.driver_motion(p.driver, s0.t).f);
        }
    }
    // y's layout: the free coordinates and speeds
    std::vector<char> fixed_s(ns_, 0), fixed_u(nu_, 0);
    for (const Prescribed& p : prescribed_) fixed_s[p.s] = fixed_u[p.u] = 1;
    free_s_.clear();
    free_u_.clear();
    y_of_s_.assign(ns_, -1);
    for (int k = 0; k < ns_; ++k)
        if (!fixed_s[k]) {
            y_of_s_[k] = static_cast<int>(free_s_.size());
            free_s_.push_back(k);
        }
    for (int k = 0; k < nu_; ++k)
        if (!fixed_u[k]) free_u_.push_back(k);
}

void ArticulatedBody::prescribe(double t, bool coordinates) {
    for (Prescribed& p : prescribed_) {
        const TimeValue f = system_->driver_motion(p.driver, t);
        if (coordinates) {
            s_[p.s] = p.sign * f.f + p.offset;
            u_[p.u] = p.sign * f.df;
        }
        p.acceleration = p.sign * f.ddf;
    }
}

void ArticulatedBody::expand(double t, const Eigen::VectorXd& y) {
    if (prescribed_.empty()) {
        s_ = y.head(ns_);
        u_ = y.tail(nu_);
        return;
    }
    const int nys = static_cast<int>(free_s_.size());
    for (int k = 0; k < nys; ++k) s_[free_s_[k]] = y[k];
    for (size_t k = 0; k < free_u_.size(); ++k) u_[free_u_[k]] = y[nys + static_cast<int>(k)];
    prescribe(t, true);
}

void ArticulatedBody::compress(Eigen::VectorXd& y) const {
    const int nys = static_cast<int>(free_s_.size());
    y.resize(ode_size());
    for (int k = 0; k < nys; ++k) y[k] = s_[free_s_[k]];
    for (size_t k = 0; k < free_u_.size(); ++k) y[nys + static_cast<int>(k)] = u_[free_u_[k]];
}

void ArticulatedBody::build(System& system, const Topology& topology) {
    system_ = &system;
    planar_ = system.dimension() == Dimension::Planar;
    nb_ = system.body_count();
    nq_ = system.nq();
    nv_ = system.nv();
    edges_.clear();
    ns_ = nu_ = 0;
    for (int b : topology.order) {
        Edge e = tree_edge(system, topology, b);
        ns_ += e.ns;
        nu_ += e.nu;
        edges_.push_back(std::move(e));
    }
    int h = 0, d = 0;
    for (Edge& e : edges_) {
        e.h0 = h;
        e.d0 = d;
        h += 6 * e.nu;
        d += e.nu * e.nu;
    }
    hpool_.assign(h, 0.0);
    dpool_.assign(d, 0.0);
    bodies_.assign(nb_, Body{});
    sign_.assign(nb_, 1.0);
    read_inertias(system);
    size_work_vectors();
}

namespace {

// A marker's origin, axes and planar angle as 3-D quantities.
void marker_frame(const Marker& m, bool planar, Vec3& u, Mat3& A, double& angle) {
    if (planar) {
        u = Vec3(m.u_bar.x(), m.u_bar.y(), 0.0);
        A = rotation_z(m.angle);
        angle = m.angle;
    } else {
        u = m.u_bar;
        A = m.A_bar;
        angle = 0.0;
    }
}

}  // namespace

ArticulatedBody::Edge ArticulatedBody::tree_edge(System& system, const Topology& topology, int b) const {
    Edge e;
    e.body = b;
    e.parent = topology.parent_body[b];
    e.joint = topology.parent_joint[b];
    e.s0 = ns_;
    e.u0 = nu_;
    if (e.joint < 0) {  // free root: its own coordinates and velocities
        e.ns = planar_ ? 3 : 7;
        e.nu = planar_ ? 3 : 6;
        return e;
    }
    const JointInfo& info = system.joint(e.joint);
    const bool forward = info.bodies[1] == b;
    e.child_slot = forward ? 1 : 0;
    e.parent_slot = forward ? 0 : 1;
    marker_frame(info.markers.at(e.parent_slot), planar_, e.u_p, e.A_p, e.angle_p);
    marker_frame(info.markers.at(e.child_slot), planar_, e.u_c, e.A_c, e.angle_c);
    e.p_p = euler_parameters_from_rotation(e.A_p);
    e.p_c = euler_parameters_from_rotation(e.A_c);
    std::vector<RelativeMotion::Freedom> list = info.joint->relative_motion()->freedoms;
    if (!forward) std::reverse(list.begin(), list.end());  // the inverse motion's freedoms
    int s = ns_, u = nu_;
    for (const RelativeMotion::Freedom& f : list) {
        Freedom g{f.kind, f.axis.normalized(), f.kind == RelativeMotion::Kind::Helical ? f.pitch : 0.0, s, u};
        const bool ball = f.kind == RelativeMotion::Kind::Ball;
        s += ball ? 4 : 1;
        u += ball ? 3 : 1;
        e.freedoms.push_back(g);
    }
    e.ns = s - ns_;
    e.nu = u - nu_;
    return e;
}

void ArticulatedBody::read_inertias(System& system) {
    // the constant per-body blocks of M (read from the sparse matrix: never densify it)
    mass_.assign(nb_, Mat6::Zero());
    std::vector<Mat6>& blocks = mass_;
    const int nvb = planar_ ? 3 : 6;
    const Eigen::SparseMatrix<double>& Ms = system.mass_matrix();
    for (int col = 0; col < Ms.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(Ms, col); it; ++it)
            if (it.row() / nvb == col / nvb) blocks[col / nvb](it.row() % nvb, col % nvb) = it.value();
    for (const Edge& e : edges_) {
        Body& body = bodies_[e.body];
        if (planar_) {
            body.m = blocks[e.body](0, 0);
            body.J = blocks[e.body](2, 2) * Mat3::Identity();  // out-of-plane entries are never excited
        } else {
            body.m = blocks[e.body](0, 0);
            body.J = blocks[e.body].bottomRightCorner<3, 3>();
        }
    }
}

void ArticulatedBody::size_work_vectors() {
    state_.set_zero(nq_, nv_);
    Q_.setZero(nv_);
    udot_.setZero(nu_);
    s_.setZero(ns_);
    u_.setZero(nu_);
    // y = [s; u] until prescribe_driven_joints() takes driven freedoms out
    prescribed_.clear();
    free_s_.resize(ns_);
    free_u_.resize(nu_);
    y_of_s_.resize(ns_);
    for (int k = 0; k < ns_; ++k) free_s_[k] = y_of_s_[k] = k;
    for (int k = 0; k < nu_; ++k) free_u_[k] = k;
}

void ArticulatedBody::articulated(double t, const Eigen::VectorXd& Q, Eigen::VectorXd& udot) {
    for (const Edge& e : edges_) {
        Body& b = bodies_[e.body];
        b.P.setZero();
        b.P.topLeftCorner<3, 3>().diagonal().setConstant(b.m);
        b.P.bottomRightCorner<3, 3>() = b.J;
        b.z = -to6(Q, e.body);
    }
    // leaves to root: articulated inertias and bias forces
    for (auto it = edges_.rbegin(); it != edges_.rend(); ++it) {
        Body& c = bodies_[it->body];
        const auto Hc = H(*it);
        if (it->prescribed >= 0) {  // known udot: the whole articulated inertia passes to the parent
            if (it->parent < 0) continue;
            const double ud = prescribed_[it->prescribed].acceleration;
            Body& p = bodies_[it->parent];
            add_phiT_X_phi(c, c.P, p.P);
            p.z.noalias() += phiT_mul(c, c.P * (c.a + Hc.col(0) * ud) + c.z);
            continue;
        }
        const Mat6X U = c.P * Hc;
        const MatXX6 D = Hc.transpose() * U;
        Eigen::LLT<MatXX6> llt(D);
        if (llt.info() != Eigen::Success)
            throw DynamicsError(t, "embedding: the articulated inertia of body '" + system_->body(it->body).name +
                                       "' is singular across its joint");
        auto Di = Dinv(*it);
        Di = llt.solve(MatXX6::Identity(it->nu, it->nu));
        if (it->parent < 0) continue;
        const Mat6X UD = U * Di;
        const Mat6 Pa = c.P - UD * U.transpose();
        const Vec6 za = Pa * c.a + c.z - UD * (Hc.transpose() * c.z);
        Body& p = bodies_[it->parent];
        add_phiT_X_phi(c, Pa, p.P);
        p.z.noalias() += phiT_mul(c, za);
    }
    // root to leaves: joint and body accelerations, joint constraint forces
    udot.resize(nu_);
    for (const Edge& e : edges_) {
        Body& c = bodies_[e.body];
        Vec6 base = c.a;
        if (e.parent >= 0) base.noalias() += phi_mul(c, bodies_[e.parent].vdot);
        const auto Hc = H(e);
        if (e.prescribed >= 0) {
            const double ud = prescribed_[e.prescribed].acceleration;
            udot[e.u0] = ud;
            c.vdot = base + Hc.col(0) * ud;
            c.f = c.P * c.vdot + c.z;
            continue;
        }
        const Mat6X U = c.P * Hc;
        const VecX6 ud = -Dinv(e) * (U.transpose() * base + Hc.transpose() * c.z);
        udot.segment(e.u0, e.nu) = ud;
        c.vdot = base + Hc * ud;
        c.f = c.P * c.vdot + c.z;
    }
    if (!udot.allFinite()) throw NonFiniteMotion(t, "non-finite accelerations: the motion diverged");
}

void ArticulatedBody::vdot_system(Eigen::VectorXd& vdot) {
    vdot.resize(nv_);
    for (int b = 0; b < nb_; ++b) {
        const Vec6& a = bodies_[b].vdot;
        if (planar_)
            vdot.segment<3>(3 * b) << a[0], a[1], a[5];
        else
            vdot.segment<6>(6 * b) = a;
    }
}

void ArticulatedBody::to_ode(const State& state, Eigen::VectorXd& y) {
    joint_coordinates(state);
    compress(y);
}

void ArticulatedBody::from_ode(double t, const Eigen::VectorXd& y, State& state) {
    expand(t, y);
    kinematics(s_, u_);
    write_state(t, state);
}

void ArticulatedBody::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    expand(t, y);
    kinematics(s_, u_);
    write_state(t, state_);
    system_->generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged");
    articulated(t, Q_, udot_);
    write_ydot(y, ydot);
}

void ArticulatedBody::write_ydot(const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (prescribed_.empty()) {
        ydot.resize(ns_ + nu_);
        coordinate_rates(y, ydot);
        ydot.tail(nu_) = udot_;
        return;
    }
    full_y_.resize(ns_ + nu_);
    full_y_ << s_, u_;
    full_ydot_.resize(ns_ + nu_);
    coordinate_rates(full_y_, full_ydot_);
    const int nys = static_cast<int>(free_s_.size());
    ydot.resize(ode_size());
    for (int k = 0; k < nys; ++k) ydot[k] = full_ydot_[free_s_[k]];
    for (size_t k = 0; k < free_u_.size(); ++k) ydot[nys + static_cast<int>(k)] = udot_[free_u_[k]];
}

void ArticulatedBody::coordinate_rates(const Eigen::VectorXd& y, Eigen::VectorXd& ydot) const {
    // coordinate rates: sdot = u for 1-DOF freedoms; Euler parameters pdot = 1/2 Gbar^T wbar (book Eq. 8.48)
    const auto u = y.tail(nu_);
    for (const Edge& e : edges_) {
        if (e.joint < 0) {
            if (planar_) {
                ydot.segment<3>(e.s0) = u.segment<3>(e.u0);
            } else {
                ydot.segment<3>(e.s0) = u.segment<3>(e.u0);
                const Vec4 p = y.segment<4>(e.s0 + 3);
                ydot.segment<4>(e.s0 + 3) = 0.5 * euler_Gbar(p).transpose() * u.segment<3>(e.u0 + 3);
            }
            continue;
        }
        for (const Freedom& f : e.freedoms) {
            if (f.kind == RelativeMotion::Kind::Ball)
                ydot.segment<4>(f.s) = 0.5 * euler_Gbar(y.segment<4>(f.s)).transpose() * u.segment<3>(f.u);
            else
                ydot[f.s] = u[f.u];
        }
    }
}

bool ArticulatedBody::project(double /*t*/, Eigen::VectorXd& y) {
    // a quaternion's four entries stay adjacent in y (only 1-DOF freedoms are prescribed)
    for (const Edge& e : edges_) {
        if (e.joint < 0 && !planar_) y.segment<4>(y_of_s_[e.s0 + 3]).normalize();
        for (const Freedom& f : e.freedoms)
            if (f.kind == RelativeMotion::Kind::Ball) y.segment<4>(y_of_s_[f.s]).normalize();
    }
    return y.allFinite();
}

void ArticulatedBody::accelerations(const State& state, Eigen::VectorXd& vdot) {
    joint_coordinates(state);  // the driven joints' coordinates and speeds as the state has them
    prescribe(state.t, false);
    kinematics(s_, u_);
    system_->generalized_forces(state, Q_);
    articulated(state.t, Q_, udot_);
    vdot_system(vdot);
}

void ArticulatedBody::multipliers(const State& state, Eigen::VectorXd& lambda) {
    Eigen::VectorXd vdot;
    accelerations(state, vdot);
    ConstraintValues cv;
    system_->constraints(state, cv, true);
    lambda.setZero(system_->constraint_rows(true));
    tree_joint_multipliers(cv, lambda);
}

void ArticulatedBody::tree_joint_multipliers(const ConstraintValues& cv, Eigen::VectorXd& lambda) const {
    const int nvb = planar_ ? 3 : 6;
    for (const Edge& e : edges_) {
        if (e.joint < 0) continue;
        const JointInfo& info = system_->joint(e.joint);
        // a prescribed joint's force along its freedom is the driver's: its row joins the joint's
        const int driver_row = e.prescribed >= 0 ? system_->driver(prescribed_[e.prescribed].driver).row : -1;
        const int rows = info.rows + (driver_row >= 0 ? 1 : 0);
        const Body& c = bodies_[e.body];
        // the joint's generalized constraint forces on its bodies: f_c on the child,
        // -Phi^T f_c on the parent; Q_c = -J^T lambda (book Eqs. 6.128, 6.146)
        Vec6 on[2];
        on[e.child_slot] = c.f;
        on[e.parent_slot] = -phiT_mul(c, c.f);
        Eigen::MatrixXd Jk = Eigen::MatrixXd::Zero(rows, 2 * nvb);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * nvb);
        for (int slot = 0; slot < 2; ++slot) {
            const int body = info.bodies[slot];
            if (body < 0) continue;
            for (int k = 0; k < nvb; ++k) {
                const int col = body * nvb + k;
                for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, col); it; ++it)
                    if (it.row() >= info.first_row && it.row() < info.first_row + info.rows)
                        Jk(it.row() - info.first_row, slot * nvb + k) = it.value();
                    else if (it.row() == driver_row)
                        Jk(info.rows, slot * nvb + k) = it.value();
                g[slot * nvb + k] = planar_ ? on[slot][k == 2 ? 5 : k] : on[slot][k];
            }
        }
        // J_k^T lambda_k = -g (least squares on the joint's own rows)
        const Eigen::VectorXd l = Jk.transpose().colPivHouseholderQr().solve(-g);
        lambda.segment(info.first_row, info.rows) = l.head(info.rows);
        if (driver_row >= 0) lambda[driver_row] = l[info.rows];
    }
}

}  // namespace mbd::articulated
