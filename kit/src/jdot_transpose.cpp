// Jdot^T mu by coloured polarization of gamma: see jdot_transpose.hpp.
#include <mbd/kit/jdot_transpose.hpp>

#include <algorithm>

namespace mbd {

void JdotTranspose::bind(System& system) {
    planar_ = system.dimension() == Dimension::Planar;
    nvb_ = velocities_per_body(system.dimension());
    const int bodies = system.body_count();
    rows_of_body_.assign(bodies, {});
    std::vector<std::vector<int>> neighbours(bodies);
    auto add_rows = [&](const std::vector<int>& connected, int first, int count) {
        for (int b : connected) {
            if (b < 0) continue;
            for (int r = first; r < first + count; ++r) rows_of_body_[b].push_back(r);
            for (int other : connected)
                if (other >= 0 && other != b) neighbours[b].push_back(other);
        }
    };
    first_component_ = 0;
    bool translation_free = true;
    analytic_ = false;
    for (int j = 0; j < system.joint_count(); ++j) {
        const Joint* joint = system.joint(j).joint.get();
        if (joint && joint->has_gamma_velocity_transpose()) {  // the joint's own product: not probed
            analytic_ = true;
            continue;
        }
        add_rows(system.joint(j).bodies, system.joint(j).first_row, system.joint(j).rows);
        translation_free = translation_free && joint && !joint->gamma_depends_on_translation();
    }
    // a driver's row is its joint's coordinate, which the joint's answer covers
    for (int d = 0; d < system.driver_count(); ++d) {
        const JointInfo& driven = system.joint(system.driver(d).joint);
        add_rows(driven.bodies, system.driver(d).row, 1);
        translation_free = translation_free && driven.joint && !driven.joint->gamma_depends_on_translation();
    }
    if (translation_free) first_component_ = planar_ ? 2 : 3;
    // greedy colouring in body order: the least colour no neighbour has
    std::vector<int> colour(bodies, -1);
    colours_ = 0;
    std::vector<char> taken;
    for (int b = 0; b < bodies; ++b) {
        if (rows_of_body_[b].empty()) continue;  // a free body: gamma does not depend on it
        taken.assign(colours_ + 1, 0);
        for (int other : neighbours[b])
            if (colour[other] >= 0) taken[colour[other]] = 1;
        int c = 0;
        while (taken[c]) ++c;
        colour[b] = c;
        colours_ = std::max(colours_, c + 1);
    }
    bodies_of_colour_.assign(colours_, {});
    for (int b = 0; b < bodies; ++b)
        if (colour[b] >= 0) bodies_of_colour_[colour[b]].push_back(b);
    probe_.q.setZero(system.nq());
    probe_.v.setZero(system.nv());
    gamma_plus_.setZero(system.constraint_rows(true));
    gamma_minus_.setZero(system.constraint_rows(true));
    Jt_mu_.setZero(system.nv());
}

void JdotTranspose::apply(System& system, const State& state, const Eigen::SparseMatrix<double>& J,
                          const Eigen::VectorXd& mu, Eigen::VectorXd& out) {
    out.setZero(state.v.size());
    if (analytic_) {  // -D^T mu / 2 over the joints that give D^T mu themselves
        system.gamma_velocity_transpose(state, mu, out);
        out *= -0.5;
    }
    probe_.t = state.t;
    probe_.q = state.q;
    // the polarization step: exact for any s (gamma is quadratic in v); s of the size of v keeps
    // the round-off of gamma(v +- w) relative to D w near machine precision
    const double s = std::max(state.v.lpNorm<Eigen::Infinity>(), 1e-3);
    for (int colour = 0; colour < colours_; ++colour)
        for (int component = first_component_; component < nvb_; ++component) {
            probe_.v = state.v;
            for (int b : bodies_of_colour_[colour]) probe_.v[b * nvb_ + component] += s;
            system.constraint_gamma(probe_, gamma_plus_, true);
            probe_.v = state.v;
            for (int b : bodies_of_colour_[colour]) probe_.v[b * nvb_ + component] -= s;
            system.constraint_gamma(probe_, gamma_minus_, true);
            // row r of D w / s is D(r, c) for the one column c of this group that row r holds
            const double scale = -0.25 / s;  // -D^T mu / 2, D w = (gamma(v + w) - gamma(v - w)) / 2
            for (int b : bodies_of_colour_[colour]) {
                double sum = 0.0;
                for (int r : rows_of_body_[b]) sum += (gamma_plus_[r] - gamma_minus_[r]) * mu[r];
                out[b * nvb_ + component] += scale * sum;
            }
        }
    if (planar_) return;
    // - (omega_v x (J^T mu)_rot) / 2 per body
    Jt_mu_.noalias() = J.transpose() * mu;
    for (int b = 0; b < static_cast<int>(out.size()) / 6; ++b) {
        const Eigen::Vector3d w = state.v.segment<3>(6 * b + 3);
        const Eigen::Vector3d y = Jt_mu_.segment<3>(6 * b + 3);
        out.segment<3>(6 * b + 3) -= 0.5 * w.cross(y);
    }
}

void JdotTranspose::times(System& system, const State& state, const Eigen::SparseMatrix<double>& J,
                          const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::VectorXd& out) {
    probe_.t = state.t;
    probe_.q = state.q;
    probe_.v = state.v + w;
    system.constraint_gamma(probe_, gamma_plus_, true);
    probe_.v = state.v - w;
    system.constraint_gamma(probe_, gamma_minus_, true);
    out = gamma_plus_ - gamma_minus_;
    out *= -0.25;
    if (planar_) return;
    // the Lie bracket of the body-axis angular-velocity fields, Lambda(v) w = omega_v x omega_w
    Jt_mu_.setZero(state.v.size());
    for (int b = 0; b < static_cast<int>(state.v.size()) / 6; ++b)
        Jt_mu_.segment<3>(6 * b + 3) = state.v.segment<3>(6 * b + 3).cross(w.segment<3>(6 * b + 3));
    out.noalias() += 0.5 * (J * Jt_mu_);
}

}  // namespace mbd
