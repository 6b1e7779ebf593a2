// The model's events and Newton's impact law on the constrained system (contact_events.hpp).
#include <mbd/contact_events.hpp>

#include <mbd/sdk/text.hpp>

#include <Eigen/QR>

#include <cmath>

namespace mbd {

ContactEvents::ContactEvents(ModelSystem& system) : system_(system) {
    const Model& m = system.model();
    int widest = 0;
    for (size_t f = 0; f < m.forces.size(); ++f) {
        const int n = m.forces[f].force->event_count();
        for (int k = 0; k < n; ++k) entries_.push_back({static_cast<int>(f), k});
        widest = std::max(widest, n);
    }
    element_g_.resize(widest);
    element_G_.resize(velocities_per_body(m.dimension) * 2);
    G_.resize(m.nv());
    w_.resize(m.nv());
    if (!entries_.empty()) mass_.compute(system.mass_matrix());
}

std::string ContactEvents::describe(int event) const {
    const Entry& e = entries_.at(event);
    const ForceInstance& f = system_.model().forces[e.force];
    const std::string name = f.force->event_name(e.local);
    return f.type + " '" + f.name + "'" + (name.empty() ? " event " + std::to_string(e.local) : " (" + name + ")");
}

std::string ContactEvents::first_element() const {
    if (entries_.empty()) return std::string();
    const ForceInstance& f = system_.model().forces[entries_.front().force];
    return f.type + " '" + f.name + "'";
}

void ContactEvents::values(const State& state, Eigen::VectorXd& g) {
    g.resize(count());
    Data& data = system_.data();
    data.pose(state);
    int row = 0;
    const Model& m = system_.model();
    while (row < count()) {
        const ForceInstance& f = m.forces[entries_[row].force];
        const int n = f.force->event_count();
        data.poses.fill(f.bodies, state.t, data.view);
        auto local = element_g_.head(n);
        f.force->event_values(data.view, local);
        g.segment(row, n) = local;
        row += n;
    }
}

EventImpact ContactEvents::gradient(const State& state, int event) {
    const Model& m = system_.model();
    const Entry& e = entries_[event];
    const ForceInstance& f = m.forces[e.force];
    const int nvb = velocities_per_body(m.dimension);
    Data& data = system_.data();
    data.pose(state);
    data.poses.fill(f.bodies, state.t, data.view);
    if (element_G_.size() < nvb * static_cast<int>(f.bodies.size())) element_G_.resize(nvb * f.bodies.size());
    auto local = element_G_.head(nvb * static_cast<int>(f.bodies.size()));
    local.setZero();
    const EventImpact impact = f.force->event_impact(e.local, data.view, local);
    G_.setZero();
    for (size_t b = 0; b < f.bodies.size(); ++b)
        if (f.bodies[b] != kGround) G_.segment(m.v_offset(f.bodies[b]), nvb) += local.segment(nvb * b, nvb);
    return impact;
}

void ContactEvents::constrained_response(const State& state) {
    w_ = mass_.solve(G_);  // M^-1 G^T
    system_.constraints(state, cv_, true);
    if (cv_.J.rows() == 0) return;
    // w = u - M^-1 J^T S^+ J u with S = J M^-1 J^T: dense, impacts are rare (complete
    // orthogonal decomposition: redundant joint rows are consistent, not singular)
    const Eigen::MatrixXd J = cv_.J;
    const Eigen::MatrixXd MinvJt = mass_.solve(Eigen::MatrixXd(J.transpose()));
    const Eigen::MatrixXd S = J * MinvJt;
    const Eigen::VectorXd mu = S.completeOrthogonalDecomposition().solve(J * w_);
    w_ -= MinvJt * mu;
}

bool ContactEvents::handle(State& state, const std::vector<int>& crossed, std::vector<int>& side,
                           std::vector<EventRecord>& log) {
    bool changed = false;
    for (int event : crossed) {
        const Entry& entry = entries_[event];
        const ForceInstance& f = system_.model().forces[entry.force];
        const EventImpact impact = gradient(state, event);
        EventRecord record{state.t, f.name, f.force->event_name(entry.local), side[event] > 0 ? "open" : "close",
                           G_.dot(state.v), 0.0};
        const double approach = record.rate_before;
        if (side[event] < 0 && impact.impact) {
            // a closing without approach speed (a grazing touch, or speeds below what the
            // tolerance resolves) is a rest as well
            const bool rests = !(approach < 0.0) || impact.restitution * -approach < impact.rest_velocity;
            if (rests && !impact.holds_resting)
                throw DynamicsError(state.t, describe(event) + " comes to rest at t = " + format_time(state.t) +
                                                 (approach < 0.0
                                                      ? " (rebound speed " +
                                                            format_number(impact.restitution * -approach, 3) +
                                                            " below its rest_velocity " +
                                                            format_number(impact.rest_velocity, 3) + ")"
                                                      : " (it closes without approach speed)") +
                                                 ": give it a compliant law (law: hunt_crossley with stiffness) to "
                                                 "hold a resting contact, or end the run before it settles");
            record.kind = rests ? "rest" : "impact";
            side[event] = rests ? -1 : +1;
            if (!(approach < 0.0)) {  // nothing to stop: the law takes the contact as it is
                record.rate_after = approach;
                log.push_back(record);
                continue;
            }
            const double e = rests ? 0.0 : impact.restitution;
            constrained_response(state);
            const double inverse_mass = G_.dot(w_);
            if (!(inverse_mass > 1e-14 * std::max(1.0, G_.squaredNorm())))
                throw DynamicsError(state.t, describe(event) + " is hit at t = " + format_time(state.t) +
                                                 " but its coordinate cannot move: the joints and drivers hold it "
                                                 "fixed, so no impulse can act on it (remove the stop or the driver)");
            const double P = -(1.0 + e) * approach / inverse_mass;
            state.v += P * w_;
            changed = true;
        }
        record.rate_after = G_.dot(state.v);
        log.push_back(record);
    }
    return changed;
}

void ContactEvents::check_start(const State& state, const std::vector<int>& side) {
    for (int event = 0; event < count(); ++event) {
        if (side[event] > 0) continue;
        const EventImpact impact = gradient(state, event);
        if (impact.impact && !impact.holds_resting)
            throw DynamicsError(state.t, describe(event) + " starts closed (its gap is negative at t = 0) and has no "
                                                           "compliant law to push it back: start the motion inside "
                                                           "its limits");
    }
}

void ContactProblem::event_values(double t, const Eigen::VectorXd& y, Eigen::VectorXd& g) {
    formulation_.from_ode(t, y, state_);
    events_.values(state_, g);
}

bool ContactProblem::handle_events(double t, Eigen::VectorXd& y, const std::vector<int>& crossed,
                                   std::vector<int>& side) {
    formulation_.from_ode(t, y, state_);
    state_.t = t;
    if (!events_.handle(state_, crossed, side, log_)) return false;
    formulation_.to_ode(state_, y);
    if (!formulation_.project(t, y))
        throw DynamicsError(t, "projection onto the constraint manifold failed after the impact at t = " +
                                   format_time(t));
    return true;
}

}  // namespace mbd
