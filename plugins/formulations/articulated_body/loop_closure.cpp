// The recursive path with loop-closure rows: see loop_closure.hpp.
#include "loop_closure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/sdk/text.hpp>

namespace mbd::articulated {

void LoopClosure::bind(System& system, const FormulationOptions& options) {
    std::string reason;
    if (!closure_embedding_possible(system, &reason))
        throw InputError("", "embedding formulation, path: closure: " + reason + " (use path: dense or auto)");
    const Topology topology = analyse_closure_topology(system);
    build(system, topology);
    projection_tolerance_ = options.newton.tolerance;
    newton_iterations_ = options.newton.iterations;
    // the closure rows: every row of a joint that is not a tree edge, then the drivers'
    rows_.clear();
    for (const auto* list : {&topology.cut_joints, &topology.other_joints})
        for (int j : *list)
            for (int r = 0; r < system.joint(j).rows; ++r) rows_.push_back(system.joint(j).first_row + r);
    std::sort(rows_.begin(), rows_.end());
    for (int d = 0; d < system.driver_count(); ++d) rows_.push_back(system.driver(d).row);
    const int nrows = system.constraint_rows(true), nc = static_cast<int>(rows_.size());
    row_of_.assign(nrows, -1);
    for (int k = 0; k < nc; ++k) row_of_[rows_[k]] = k;
    H6_.setZero(6 * nb_, nu_);
    H_.setZero(nv_, nu_);
    MH_.setZero(nv_, nu_);
    Mu_.setZero(nu_, nu_);
    Phi_.setZero(nc, nu_);
    a6_.setZero(6 * nb_);
    for (Eigen::VectorXd* v : {&a_, &work_, &vdot_}) v->setZero(nv_);
    for (Eigen::VectorXd* v : {&gamma_u_, &C_c_, &Ct_c_, &lambda_c_, &r_}) v->setZero(nc);
    for (Eigen::VectorXd* v : {&h_, &du_}) v->setZero(nu_);
    ytmp_.setZero(ns_ + nu_);
    cv_.C.setZero(nrows);
    cv_.C_t.setZero(nrows);
    cv_.gamma.setZero(nrows);
    saddle_.resize(nu_, nc);
    dropped_.clear();
    is_dropped_.assign(nc, 0);
    saddle_.leave_out(dropped_);
    log_ = options.log_choices.value_or(true) ? options.log : MessageLog::silent();
    find_redundant_rows(options);
}

void LoopClosure::joint_space(double t) {
    write_state(t, state_);
    system_->constraints(state_, cv_, true);
    // H = dv/du and a = vdot(udot = 0), parent before child: v_c = Phi v_p + H_e u_e
    for (const Edge& e : edges_) {
        const Body& c = bodies_[e.body];
        const int r = 6 * e.body;
        if (e.parent >= 0) {
            const int p = 6 * e.parent;
            H6_.middleRows<3>(r) = H6_.middleRows<3>(p);
            H6_.middleRows<3>(r).noalias() += c.S * H6_.middleRows<3>(p + 3);
            H6_.middleRows<3>(r + 3).noalias() = c.E * H6_.middleRows<3>(p + 3);
            a6_.segment<6>(r) = phi_mul(c, a6_.segment<6>(p)) + c.a;
        } else {
            H6_.middleRows<6>(r).setZero();
            a6_.segment<6>(r) = c.a;
        }
        H6_.block(r, e.u0, 6, e.nu) += H(e);
    }
    if (planar_) {
        for (int b = 0; b < nb_; ++b)
            for (int k = 0; k < 3; ++k) {
                H_.row(3 * b + k) = H6_.row(6 * b + (k == 2 ? 5 : k));
                a_[3 * b + k] = a6_[6 * b + (k == 2 ? 5 : k)];
            }
    } else {
        H_ = H6_;
        a_ = a6_;
    }
    // the closure rows in joint space: Phi_u = J_c H, gamma_u = gamma_c - J_c a
    for (int k = 0; k < static_cast<int>(rows_.size()); ++k) {
        C_c_[k] = cv_.C[rows_[k]];
        Ct_c_[k] = cv_.C_t[rows_[k]];
        gamma_u_[k] = cv_.gamma[rows_[k]];
    }
    Phi_.setZero();
    for (int col = 0; col < cv_.J.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(cv_.J, col); it; ++it) {
            const int k = row_of_[it.row()];
            if (k < 0) continue;
            Phi_.row(k) += it.value() * H_.row(col);
            gamma_u_[k] -= it.value() * a_[col];
        }
}

void LoopClosure::joint_mass(bool with_h) {
    const int nvb = planar_ ? 3 : 6;
    for (int b = 0; b < nb_; ++b) {
        const auto Mb = mass_[b].topLeftCorner(nvb, nvb);
        MH_.middleRows(nvb * b, nvb).noalias() = Mb * H_.middleRows(nvb * b, nvb);
        if (with_h) {  // Q - M a
            work_.segment(nvb * b, nvb) = Q_.segment(nvb * b, nvb);
            work_.segment(nvb * b, nvb).noalias() -= Mb * a_.segment(nvb * b, nvb);
        }
    }
    // coefficient-based: a blocked product of this size would take its workspace from the heap
    Mu_.noalias() = H_.transpose().lazyProduct(MH_);
    if (with_h) h_.noalias() = H_.transpose() * work_;
}

void LoopClosure::dynamics(double t) {
    double residual = std::numeric_limits<double>::infinity();
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (!factor(t, attempt > 0))
            throw DynamicsError(t, "embedding (closure path): the joint-space mass matrix H^T M H is not positive "
                                   "definite (a tree freedom moves no mass)");
        saddle_.solve(Phi_, h_, gamma_u_, udot_, lambda_c_);
        const bool finite = udot_.allFinite() && lambda_c_.allFinite();
        if (finite && !saddle_.robust()) return;
        if (finite) {
            // the acceleration constraints Phi_u udot = gamma_u must hold (Eq. 6.139): the
            // minimum-norm path leaves a residual only in dependent directions, not an O(1) one
            r_.noalias() = Phi_ * udot_;
            r_ -= gamma_u_;
            double scale = 1.0 + gamma_u_.lpNorm<Eigen::Infinity>();
            for (int k = 0; k < Phi_.rows(); ++k) {
                if (is_dropped_[k]) r_[k] = 0.0;
                scale = std::max(scale, Phi_.row(k).cwiseProduct(udot_.transpose()).cwiseAbs().maxCoeff());
            }
            residual = r_.size() ? r_.lpNorm<Eigen::Infinity>() / scale : 0.0;
            if (residual <= 1e-2) return;
        }
        if (saddle_.robust()) break;
    }
    char detail[96];
    std::snprintf(detail, sizeof detail, "Phi_u udot = gamma_u has no solution, relative residual %.2g", residual);
    saddle_error(t, detail);
}

void LoopClosure::saddle_error(double t, const char* what) const {
    // the closure rows that depend on the others: the last columns of a column-pivoted QR of Phi_u^T
    std::string names;
    const int nc = static_cast<int>(rows_.size());
    if (nc > 0) {
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Phi_.transpose());
        qr.setThreshold(1e-6);
        const int rank = std::min(static_cast<int>(qr.rank()), nc - 1);
        for (int k = rank; k < nc && k < rank + 8; ++k)
            names += (names.empty() ? "" : ", ") + system_->describe_row(rows_[qr.colsPermutation().indices()[k]]);
    }
    throw DynamicsError(t, std::string("singular saddle point (embedding, closure path: ") + what +
                               "): the loop-closure rows are dependent in joint coordinates: " + names +
                               " (remove redundant joints, or check for a locked or singular position)");
}

void LoopClosure::find_redundant_rows(const FormulationOptions& options) {
    if (rows_.empty()) return;
    const State start = assembled_initial_state(*system_);
    to_ode(start, ytmp_);
    s_ = ytmp_.head(ns_);
    u_ = ytmp_.tail(nu_);
    kinematics(s_, u_);
    joint_space(0.0);
    joint_mass(false);
    if (!saddle_.factor(Mu_, Phi_, false) || !saddle_.robust()) return;  // full rank (or rhs will say why not)
    // the least independent rows of W = Phi_u L^-T: the last columns of a column-pivoted QR of W^T
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(saddle_.Wt());
    qr.setThreshold(1e-8);
    const int nc = static_cast<int>(rows_.size()), rank = static_cast<int>(qr.rank());
    std::string names;
    for (int k = rank; k < nc; ++k) dropped_.push_back(qr.colsPermutation().indices()[k]);
    std::sort(dropped_.begin(), dropped_.end());
    for (int k : dropped_) {
        is_dropped_[k] = 1;
        names += (names.empty() ? "" : ", ") + system_->describe_row(rows_[k]);
    }
    saddle_.leave_out(dropped_);
    if (!dropped_.empty())
        options.log("embedding: " + std::to_string(dropped_.size()) + " redundant constraint row" +
                    (dropped_.size() == 1 ? "" : "s") + " dropped: " + names);
}

bool LoopClosure::factor(double t, bool robust) {
    if (!saddle_.factor(Mu_, Phi_, robust)) return false;
    // which of the dependent rows is left out can change along the motion (the Bricard's): when
    // the kept rows grow ill-conditioned, choose again (as the augmented formulation does)
    if (dropped_.empty() || robust || saddle_.least_relative_pivot() > 1e-6) return true;
    std::vector<int> before = dropped_;
    saddle_.leave_out({});
    saddle_.factor(Mu_, Phi_, true);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(saddle_.Wt());
    const int nc = static_cast<int>(rows_.size()), count = static_cast<int>(before.size());
    dropped_.assign(qr.colsPermutation().indices().data() + (nc - count), qr.colsPermutation().indices().data() + nc);
    std::sort(dropped_.begin(), dropped_.end());
    std::fill(is_dropped_.begin(), is_dropped_.end(), 0);
    std::string names;
    for (int k : dropped_) {
        is_dropped_[k] = 1;
        names += (names.empty() ? "" : ", ") + system_->describe_row(rows_[k]);
    }
    saddle_.leave_out(dropped_);
    if (dropped_ != before) log_("embedding: t = " + format_time(t) + ": redundant constraint row" +
                                         (count == 1 ? "" : "s") + " re-selected: " + names);
    return saddle_.factor(Mu_, Phi_, false);
}

void LoopClosure::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    s_ = y.head(ns_);
    u_ = y.tail(nu_);
    kinematics(s_, u_);
    joint_space(t);
    system_->generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged");
    joint_mass(true);
    dynamics(t);
    ydot.resize(ns_ + nu_);
    coordinate_rates(y, ydot);
    ydot.tail(nu_) = udot_;
}

void LoopClosure::advance(Eigen::VectorXd& s, const Eigen::VectorXd& du) const {
    // Euler parameters turned by the body-axis increment dpi: dp = 1/2 Gbar^T dpi (book Eq. 8.48)
    auto turn = [](auto p, const Vec3& dpi) {
        const Vec4 p0 = p;
        p = p0 + 0.5 * euler_Gbar(p0).transpose() * dpi;
        p.normalize();
    };
    for (const Edge& e : edges_) {
        if (e.joint < 0) {
            s.segment<3>(e.s0) += du.segment<3>(e.u0);
            if (!planar_) turn(s.segment<4>(e.s0 + 3), du.segment<3>(e.u0 + 3));
            continue;
        }
        for (const Freedom& f : e.freedoms) {
            if (f.kind == RelativeMotion::Kind::Ball)
                turn(s.segment<4>(f.s), du.segment<3>(f.u));
            else
                s[f.s] += du[f.u];
        }
    }
}

bool LoopClosure::project_positions(double t, Eigen::VectorXd& s, bool robust) {
    auto violation = [&] {
        double worst = 0.0;
        for (int k = 0; k < C_c_.size(); ++k)
            if (!is_dropped_[k]) worst = std::max(worst, std::abs(C_c_[k]));
        return std::isfinite(C_c_.sum()) ? worst : std::numeric_limits<double>::infinity();
    };
    const double tol = projection_tolerance_;
    for (int iteration = 0; iteration < newton_iterations_; ++iteration) {
        kinematics(s, u_);
        joint_space(t);
        const double c = violation();
        if (!std::isfinite(c)) return false;
        // at least one Newton step whenever C != 0 (a smooth map of the state: projection.hpp)
        if (c == 0.0 || (iteration > 0 && c <= tol)) return true;
        joint_mass(false);
        if (!factor(t, robust)) return false;
        r_ = C_c_;
        saddle_.correction(Phi_, r_, du_);  // the least-M_u-norm step with Phi_u ds = -C
        if (!du_.allFinite()) return false;
        advance(s, du_);
        if (du_.lpNorm<Eigen::Infinity>() <= 1e-3 * tol) {
            kinematics(s, u_);
            joint_space(t);
            return violation() <= 1e3 * tol;
        }
    }
    return false;
}

bool LoopClosure::project(double t, Eigen::VectorXd& y) {
    if (!ArticulatedBody::project(t, y)) return false;  // unit Euler parameters
    if (rows_.empty()) return true;
    ytmp_ = y;
    for (int attempt = 0; attempt < 2; ++attempt) {
        const bool robust = attempt > 0;
        s_ = ytmp_.head(ns_);
        u_ = ytmp_.tail(nu_);
        if (!project_positions(t, s_, robust)) continue;
        // velocities: u <- u - M_u^-1 Phi_u^T S^-1 (Phi_u u + C_t) (book Eq. 6.138 on the closure
        // rows), with the kinematics and joint-space rows project_positions left at the final s_
        joint_mass(false);
        if (!factor(t, robust)) continue;
        r_.noalias() = Phi_ * u_;
        r_ += Ct_c_;
        saddle_.correction(Phi_, r_, du_);
        if (!s_.allFinite() || !du_.allFinite() || !u_.allFinite()) continue;
        check_no_jump(t);
        u_ += du_;
        y.head(ns_) = s_;
        y.tail(nu_) = u_;
        return true;
    }
    return false;
}

void LoopClosure::check_no_jump(double t) {
    // drift is of the order of the integrator's local error; a velocity correction comparable
    // to the motion itself (in the kinetic-energy norm of M_u) is none: the closure rows are
    // (nearly) dependent here (a dead centre, a bifurcation like the parallelogram's flat
    // position) and the step reached another branch, or the projection would remove the motion
    h_.noalias() = Mu_ * u_;
    const double motion = std::sqrt(std::max(u_.dot(h_), 0.0));
    h_.noalias() = Mu_ * du_;
    const double change = std::sqrt(std::max(du_.dot(h_), 0.0));
    if (!(change > kJumpRatio * motion) || change <= 1e-9) return;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(saddle_.Wt());
    qr.setThreshold(1e-6);
    const int nc = static_cast<int>(rows_.size()), rank = std::min(static_cast<int>(qr.rank()), nc - 1);
    std::string names;
    for (int k = rank; k < nc && k < rank + 8; ++k)
        names += (names.empty() ? "" : ", ") + system_->describe_row(rows_[qr.colsPermutation().indices()[k]]);
    char ratio[64];
    std::snprintf(ratio, sizeof ratio, "%.3g", change / std::max(motion, 1e-300));
    throw DynamicsError(t, "singular configuration at t = " + format_time(t) +
                               " (embedding, closure path): the velocity projection onto the loop-closure rows would "
                               "change the motion by " + ratio + " of its size (kinetic-energy norm): the rows are "
                               "(nearly) dependent here and the step left the branch; joints involved: " + names +
                               "; the mechanism is at a dead centre or bifurcation: use path: dense (it re-selects "
                               "its coordinates) or a smaller tolerance");
}

void LoopClosure::solve_at(const State& state) {
    to_ode(state, ytmp_);
    s_ = ytmp_.head(ns_);
    u_ = ytmp_.tail(nu_);
    kinematics(s_, u_);
    joint_space(state.t);
    system_->generalized_forces(state_, Q_);
    joint_mass(true);
    dynamics(state.t);
    vdot_.noalias() = H_ * udot_;  // vdot = H udot + a
    vdot_ += a_;
}

void LoopClosure::accelerations(const State& state, Eigen::VectorXd& vdot) {
    solve_at(state);
    vdot = vdot_;
}

void LoopClosure::multipliers(const State& state, Eigen::VectorXd& lambda) {
    solve_at(state);
    lambda.setZero(system_->constraint_rows(true));
    for (int k = 0; k < static_cast<int>(rows_.size()); ++k) lambda[rows_[k]] = lambda_c_[k];
    // what the tree joints must supply on each body: M vdot - Q - Q_c,closure, Q_c = -J_c^T lambda_c (Eq. 6.128)
    const int nvb = planar_ ? 3 : 6;
    for (int b = 0; b < nb_; ++b)
        work_.segment(nvb * b, nvb).noalias() = mass_[b].topLeftCorner(nvb, nvb) * vdot_.segment(nvb * b, nvb);
    work_ -= Q_;
    for (int col = 0; col < cv_.J.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(cv_.J, col); it; ++it)
            if (row_of_[it.row()] >= 0) work_[col] += it.value() * lambda_c_[row_of_[it.row()]];
    // leaves to root: the force of a body's tree joint carries its subtree, f_b = g_b + sum Phi_c^T f_c
    for (const Edge& e : edges_) bodies_[e.body].f = to6(work_, e.body);
    for (auto it = edges_.rbegin(); it != edges_.rend(); ++it)
        if (it->parent >= 0) bodies_[it->parent].f += phiT_mul(bodies_[it->body], bodies_[it->body].f);
    tree_joint_multipliers(cv_, lambda);
}

}  // namespace mbd::articulated
