// Event location for the one-step integrators (event_locator.hpp).
#include "event_locator.hpp"

#include "common.hpp"

namespace mbd::integrators {

void EventLocator::start(OdeProblem& problem, double t0, const Eigen::VectorXd& y0) {
    const int n = problem.event_count();
    side_.assign(n, +1);
    crossed_.clear();
    candidates_.clear();
    crossed_.reserve(n);
    candidates_.reserve(n);
    pile_up_.reset(t0);
    if (n == 0) return;
    g_.resize(n);
    y_theta_.resize(y0.size());
    problem.event_values(t0, y0, g_);
    for (int k = 0; k < n; ++k) side_[k] = g_[k] < 0.0 ? -1 : +1;
}

bool EventLocator::left_side(OdeProblem& problem, double t, const Eigen::VectorXd& y) {
    problem.event_values(t, y, g_);
    candidates_.clear();
    for (int k = 0; k < static_cast<int>(side_.size()); ++k)
        if (crosses(k, g_[k])) candidates_.push_back(k);
    return !candidates_.empty();
}

void EventPileUpGuard::check(double t, const OdeProblem& problem, int event) {
    repeats_ = (t - last_time_ <= 1e-12 * std::max(1.0, std::abs(t))) ? repeats_ + 1 : 0;
    last_time_ = t;
    if (repeats_ > 100)
        throw DynamicsError(t, "events pile up at t = " + format_time(t) + " (" + problem.describe_event(event) +
                                   " opens and closes without end): give the stop a compliant law to hold the "
                                   "contact, or a larger rest_velocity");
}

bool EventLocator::handle(OdeProblem& problem, double t, Eigen::VectorXd& y, IntegratorStats& stats) {
    pile_up_.check(t, problem, crossed_[0]);
    for (int event : crossed_) side_[event] = -side_[event];
    stats.events += static_cast<long>(crossed_.size());
    return problem.handle_events(t, y, crossed_, side_);
}

}  // namespace mbd::integrators
